// Reach for the Spheres through the real program: listed and described,
// `arcs reconstruct --method rfts` on a built-in shape (closed, genus 0, below
// MC's Chamfer at a coarse grid, the same file at 1 and 2 threads), and clear
// errors on bad samples.
#include "tests/e2e/e2e_util.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <regex>

namespace arcs {
namespace {

using testing::Arcs;
using testing::Metric;
using testing::RunCmd;

TEST(RftsE2e, ListedAndDescribedWithEveryParameter) {
  const auto l = RunCmd(Arcs() + " list");
  ASSERT_EQ(l.code, 0) << l.output;
  EXPECT_NE(l.output.find("rfts"), std::string::npos) << l.output;
  const auto d = RunCmd(Arcs() + " describe rfts");
  ASSERT_EQ(d.code, 0) << d.output;
  for (const char* p : {"max_iterations", "tol", "min_h", "line_search", "min_t", "max_t", "dt", "batch_size",
                        "remesh_iterations", "split_ratio", "collapse_ratio", "patience", "max_stall",
                        "initial_subdivisions", "initial_radius", "max_area_ratio", "20000"})
    EXPECT_NE(d.output.find(p), std::string::npos) << p << "\n" << d.output;
}

TEST(RftsE2e, ReconstructsABuiltInShapeDeterministicallyAndBelowMc) {
  const auto dir = testing::TempDir("rfts_reconstruct");
  const std::string sdf = (dir / "blob.npy").string();
  ASSERT_EQ(RunCmd(Arcs() + " sdf shape:sphere " + sdf + " --n 10").code, 0);
  const auto r1 = RunCmd(Arcs() + " reconstruct " + sdf + " " + (dir / "r1.ply").string() +
                         " --method rfts --param batch_size=300 --threads 1");
  ASSERT_EQ(r1.code, 0) << r1.output;
  EXPECT_NE(r1.output.find("closed 1, genus 0"), std::string::npos) << r1.output;
  const auto r2 = RunCmd(Arcs() + " reconstruct " + sdf + " " + (dir / "r2.ply").string() +
                         " --method rfts --param batch_size=300 --threads 2");
  ASSERT_EQ(r2.code, 0) << r2.output;
  EXPECT_EQ(testing::ReadFile(dir / "r1.ply"), testing::ReadFile(dir / "r2.ply"));
  const auto mc = RunCmd(Arcs() + " reconstruct " + sdf + " " + (dir / "mc.ply").string() + " --method marching_cubes");
  ASSERT_EQ(mc.code, 0) << mc.output;
  const auto e_rfts = RunCmd(Arcs() + " eval " + (dir / "r1.ply").string() + " shape:sphere --samples 100000");
  const auto e_mc = RunCmd(Arcs() + " eval " + (dir / "mc.ply").string() + " shape:sphere --samples 100000");
  const double c_rfts = Metric(e_rfts.output, "chamfer_p2s"), c_mc = Metric(e_mc.output, "chamfer_p2s");
  ASSERT_GT(c_rfts, 0) << e_rfts.output;
  EXPECT_LT(c_rfts, c_mc) << "RFTS uses the sphere radii, MC only the signs' interpolation";
}

TEST(RftsE2e, BadInputGivesClearErrors) {
  const auto dir = testing::TempDir("rfts_bad");
  auto run = [&](const std::string& name, const std::string& text) {
    testing::WriteFile(dir / name, text);
    return RunCmd(Arcs() + " reconstruct " + (dir / name).string() + " " + (dir / "out.ply").string() +
                  " --method rfts");
  };
  std::string positive;
  for (int i = 0; i < 27; ++i)
    positive += std::to_string(i % 3) + " " + std::to_string((i / 3) % 3) + " " + std::to_string(i / 9) + " 0.5\n";
  const auto all_pos = run("pos.txt", positive);
  EXPECT_EQ(all_pos.code, 1);
  EXPECT_NE(all_pos.output.find("rfts: no SDF sample is negative"), std::string::npos) << all_pos.output;
  const auto nan = run("nan.txt", "0 0 0 0.5\n1 0 0 nan\n0 1 0 -0.2\n");
  EXPECT_EQ(nan.code, 1);
  EXPECT_NE(nan.output.find("nan.txt:2"), std::string::npos) << nan.output;
  const auto single = run("one.txt", "0 0 0 -0.5\n");
  EXPECT_EQ(single.code, 1);
  EXPECT_NE(single.output.find("arcs: error"), std::string::npos) << single.output;
  const auto ragged = run("ragged.txt", "0 0 0 -0.5\n1 0 0\n");
  EXPECT_EQ(ragged.code, 1);
  EXPECT_NE(ragged.output.find("ragged.txt:2"), std::string::npos) << ragged.output;
}

}  // namespace
}  // namespace arcs
