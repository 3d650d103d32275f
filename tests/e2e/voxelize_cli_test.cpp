// `arcs voxelize`: a built-in shape end to end, the written array and its
// bounds sidecar, --verify, and bad input.
#include "framework/io/npy.h"
#include "framework/io/sdf_io.h"
#include "tests/e2e/e2e_util.h"

#include <gtest/gtest.h>

namespace arcs::testing {
namespace {

TEST(VoxelizeCli, TorusShapeToOccupancyGrid) {
  const auto dir = TempDir("voxelize_cli");
  const std::string obj = (dir / "t.obj").string(), npy = (dir / "t.npy").string();
  ASSERT_EQ(RunCmd(Arcs() + " shape torus '" + obj + "'").code, 0);
  const CmdResult r = RunCmd(Arcs() + " voxelize '" + obj + "' '" + npy + "' --resolution 24 --verify --verify-random 200");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("path flood_fill"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(" 0 sign differences"), std::string::npos) << r.output;
  const NpyArray a = ReadNpy(npy);
  ASSERT_EQ(a.shape, (std::vector<std::int64_t>{24, 24, 24}));
  double occupied = 0;
  for (double v : a.data) {
    ASSERT_TRUE(v == 0.0 || v == 1.0);
    occupied += v;
  }
  // Torus normalised to longest side 2 (R = 0.7, r = 0.3): volume 2 pi^2 R r^2
  // = 1.24 of the 8 of the cube; on 24^3 nodes about 3 700 inside.
  EXPECT_GT(occupied, 0.10 * a.Size());
  EXPECT_LT(occupied, 0.22 * a.Size());
  // The centre of the torus (node ~ (11.5, 11.5, 11.5)) is outside, a point on
  // the tube's core circle inside: arr[i, j, k] is (x_i, y_j, z_k).
  EXPECT_EQ(a.data[(11 * 24 + 11) * 24 + 11], 0.0);
  EXPECT_EQ(a.data[(20 * 24 + 11) * 24 + 11], 1.0);  // x = 0.74, y = -0.04, z = -0.04
  // The SDF grid reader understands the file and its bounds sidecar.
  const SdfSamples s = ReadSdfGrid(npy, {0, 0, 0}, {5, 5, 5});
  ASSERT_TRUE(s.grid.has_value());
  EXPECT_EQ(s.grid->min[0], -1.0);
  EXPECT_EQ(s.grid->max[2], 1.0);
  // Winding output, float64, exact method, explicit bounds.
  const CmdResult w = RunCmd(Arcs() + " voxelize '" + obj + "' '" + npy +
                             "' --resolution 8 --method exact --output winding --dtype float64 --lo -1.1 --hi 1.1");
  ASSERT_EQ(w.code, 0) << w.output;
  EXPECT_NE(ReadFile(npy + ".bounds").find("-1.1"), std::string::npos);
}

TEST(VoxelizeCli, BadInput) {
  const auto dir = TempDir("voxelize_cli_bad");
  const std::string obj = (dir / "t.obj").string();
  ASSERT_EQ(RunCmd(Arcs() + " shape sphere '" + obj + "'").code, 0);
  const std::string out = "'" + (dir / "o.npy").string() + "'";
  CmdResult r = RunCmd(Arcs() + " voxelize '" + (dir / "missing.obj").string() + "' " + out);
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.output.find("missing.obj"), std::string::npos) << r.output;
  r = RunCmd(Arcs() + " voxelize '" + obj + "' " + out + " --method magic");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("method"), std::string::npos) << r.output;
  r = RunCmd(Arcs() + " voxelize '" + obj + "' " + out + " --resolution 1");
  EXPECT_EQ(r.code, 2);
  r = RunCmd(Arcs() + " voxelize '" + obj + "' " + out + " --lo 1 --hi -1");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("lo < hi"), std::string::npos) << r.output;
  r = RunCmd(Arcs() + " voxelize '" + obj + "'");
  EXPECT_EQ(r.code, 2);
  WriteFile(dir / "bad.obj", "v 0 0 0\nv 1 0 0\nf 1 2 9\n");
  r = RunCmd(Arcs() + " voxelize '" + (dir / "bad.obj").string() + "' " + out);
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.output.find("bad.obj"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace arcs::testing
