// End-to-end tests of `arcs morph` (built-in shapes and files the test writes;
// no shared data).
#include "framework/io/mesh_io.h"
#include "framework/io/npy.h"
#include "framework/voxel/morph.h"
#include "tests/e2e/e2e_util.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <regex>

namespace arcs {
namespace {

using testing::Arcs;
using testing::RunCmd;

// A closed box [0, 2] x [0, 1.2] x [0, 0.8] (12 outward triangles) as OBJ.
const char* kBoxObj =
    "v 0 0 0\nv 2 0 0\nv 2 1.2 0\nv 0 1.2 0\nv 0 0 0.8\nv 2 0 0.8\nv 2 1.2 0.8\nv 0 1.2 0.8\n"
    "f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\n"
    "f 4 1 5\nf 4 5 8\n";

std::vector<double> IousIn(const std::string& out) {
  std::vector<double> v;
  const std::regex re("iteration +[0-9]+ +IoU ([0-9.]+)");
  for (auto it = std::sregex_iterator(out.begin(), out.end(), re); it != std::sregex_iterator(); ++it)
    v.push_back(std::stod((*it)[1]));
  return v;
}

TEST(MorphCliTest, SphereToBoxRaisesIoUAndWritesMeshAndLog) {
  const auto dir = testing::TempDir("morph_cli_box");
  testing::WriteFile(dir / "box.obj", kBoxObj);
  const auto r = RunCmd(Arcs() + " morph sphere " + (dir / "box.obj").string() + " " + (dir / "out.obj").string() +
                        " --res 20 --iterations 40 --subdivisions 3 --batch 2000 --every 10 --threads 2 --log " +
                        (dir / "log.csv").string());
  ASSERT_EQ(r.code, 0) << r.output;
  // Per-iteration lines (0, 10, ..., 40).
  const std::vector<double> ious = IousIn(r.output);
  ASSERT_GE(ious.size(), 5u) << r.output;
  EXPECT_GT(ious.back(), ious.front() + 0.05) << r.output;
  EXPECT_GT(ious.back(), 0.85) << r.output;
  // The mesh is written in the box's own frame ([0, 2] x [0, 1.2] x [0, 0.8]).
  const Mesh m = ReadMesh((dir / "out.obj").string());
  EXPECT_EQ(m.NumFaces(), 1280);
  const Vec3 lo = m.V.colwise().minCoeff().transpose(), hi = m.V.colwise().maxCoeff().transpose();
  EXPECT_NEAR(lo.x(), 0.0, 0.2);
  EXPECT_NEAR(hi.x(), 2.0, 0.2);
  EXPECT_NEAR(hi.z(), 0.8, 0.2);
  const std::string log = testing::ReadFile(dir / "log.csv");
  EXPECT_EQ(log.rfind("iteration,iou,loss,active_nodes,seconds\n", 0), 0u) << log;
  EXPECT_EQ(std::count(log.begin(), log.end(), '\n'), 6) << log;  // header + iterations 0..40 by 10
}

TEST(MorphCliTest, NpyOccupancyTarget) {
  const auto dir = testing::TempDir("morph_cli_npy");
  // Occupancy of an off-centre ball on a 16^3 grid over [-1, 1]^3, numpy (nx, ny, nz) order.
  const int n = 16;
  std::vector<double> occ(n * n * n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const double x = -1 + 2.0 * i / (n - 1), y = -1 + 2.0 * j / (n - 1), z = -1 + 2.0 * k / (n - 1);
        occ[(i * n + j) * n + k] = (x - 0.2) * (x - 0.2) / 0.36 + y * y / 0.16 + z * z / 0.25 < 1 ? 1.0 : 0.0;
      }
  WriteNpy((dir / "occ.npy").string(), occ.data(), {n, n, n});
  const auto r = RunCmd(Arcs() + " morph sphere " + (dir / "occ.npy").string() + " " + (dir / "out.ply").string() +
                        " --iterations 60 --subdivisions 2 --batch 1000 --every 10");
  ASSERT_EQ(r.code, 0) << r.output;
  const std::vector<double> ious = IousIn(r.output);
  ASSERT_GE(ious.size(), 2u);
  EXPECT_GT(ious.back(), 0.8) << r.output;
  const Mesh m = ReadMesh((dir / "out.ply").string());
  EXPECT_NEAR(m.V.col(0).mean(), 0.2, 0.15);  // grid frame: the ball's centre
}

TEST(MorphCliTest, BadInputIsAClearError) {
  const auto dir = testing::TempDir("morph_cli_bad");
  testing::WriteFile(dir / "box.obj", kBoxObj);
  const std::string box = (dir / "box.obj").string(), out = (dir / "o.obj").string();
  {  // missing target file: exit 1, names the file
    const auto r = RunCmd(Arcs() + " morph sphere " + (dir / "nope.obj").string() + " " + out);
    EXPECT_EQ(r.code, 1) << r.output;
    EXPECT_NE(r.output.find("nope.obj"), std::string::npos) << r.output;
  }
  {  // missing source file
    const auto r = RunCmd(Arcs() + " morph " + (dir / "src.obj").string() + " " + box + " " + out);
    EXPECT_EQ(r.code, 1) << r.output;
    EXPECT_NE(r.output.find("src.obj"), std::string::npos) << r.output;
  }
  for (const char* bad : {"--res 2", "--res abc", "--res 100000", "--lr -1", "--iterations x", "--residual maybe",
                          "--bounds '1 2 3'"}) {
    const auto r = RunCmd(Arcs() + " morph sphere " + box + " " + out + " " + bad);
    EXPECT_EQ(r.code, 2) << bad << "\n" << r.output;
    const std::string opt = std::string(bad).substr(0, std::string(bad).find(' '));
    EXPECT_NE(r.output.find(opt.substr(2)), std::string::npos) << bad << "\n" << r.output;
  }
  {  // wrong argument count
    const auto r = RunCmd(Arcs() + " morph sphere " + box);
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find("SOURCE, TARGET and OUT"), std::string::npos) << r.output;
  }
  {  // an all-empty occupancy grid
    std::vector<double> z(8 * 8 * 8, 0.0);
    WriteNpy((dir / "empty.npy").string(), z.data(), {8, 8, 8});
    const auto r = RunCmd(Arcs() + " morph sphere " + (dir / "empty.npy").string() + " " + out);
    EXPECT_EQ(r.code, 1) << r.output;
    EXPECT_NE(r.output.find("no occupied node"), std::string::npos) << r.output;
  }
  EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
}  // namespace arcs
