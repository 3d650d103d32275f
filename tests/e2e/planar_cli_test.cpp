// The 2D path from the command line: a built-in curve -> 2D SDF grid ->
// `arcs reconstruct` (RFTA and marching squares) -> closed polylines.
#include "tests/e2e/e2e_util.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

namespace arcs::testing {
namespace {

TEST(PlanarCli, CurveToSdfToClosedPolyline) {
  const auto dir = TempDir("planar_cli");
  const std::string curve = (dir / "star.txt").string(), sdf = (dir / "star.npy").string();
  ASSERT_EQ(RunCmd(Arcs() + " shape star '" + curve + "'").code, 0);
  const CmdResult s = RunCmd(Arcs() + " sdf '" + curve + "' '" + sdf + "' --curve --n 20");
  ASSERT_EQ(s.code, 0) << s.output;
  EXPECT_NE(s.output.find("441 2D SDF samples"), std::string::npos) << s.output;
  const CmdResult r = RunCmd(Arcs() + " reconstruct '" + sdf + "' '" + (dir / "rfta.obj").string() + "'");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("(1 components, 0 open ends)"), std::string::npos) << r.output;
  const CmdResult m = RunCmd(Arcs() + " reconstruct '" + sdf + "' '" + (dir / "ms.svg").string() +
                             "' --method marching_squares");
  ASSERT_EQ(m.code, 0) << m.output;
  EXPECT_NE(ReadFile(dir / "ms.svg").find("<svg"), std::string::npos);
  // A mesh-only method on 2D samples is a clear error, not a crash.
  const CmdResult bad = RunCmd(Arcs() + " reconstruct '" + sdf + "' '" + (dir / "mc.obj").string() +
                               "' --method marching_cubes");
  EXPECT_EQ(bad.code, 1) << bad.output;
  EXPECT_NE(bad.output.find("2D"), std::string::npos) << bad.output;
}

}  // namespace
}  // namespace arcs::testing
