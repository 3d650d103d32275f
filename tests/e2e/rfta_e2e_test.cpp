// Reach for the Arcs through the real program: `arcs reconstruct` on data the
// project makes itself, determinism across thread counts, bad input, and the
// reduced Table 1 experiment.
#include "tests/e2e/e2e_util.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <regex>

namespace arcs {
namespace {

using testing::Arcs;
using testing::Metric;
using testing::RunCmd;

TEST(RftaE2e, ReconstructIsClosedBeatsMcAndIsIdenticalAtOneAndTwoThreads) {
  const auto dir = testing::TempDir("rfta_reconstruct");
  const std::string sdf = (dir / "torus.npy").string();
  ASSERT_EQ(RunCmd(Arcs() + " sdf shape:torus " + sdf + " --n 14").code, 0);
  const std::string p = " --param iterations=3";
  const auto r1 = RunCmd(Arcs() + " reconstruct " + sdf + " " + (dir / "t1.ply").string() + p + " --threads 1");
  ASSERT_EQ(r1.code, 0) << r1.output;
  EXPECT_NE(r1.output.find("closed 1, genus 1"), std::string::npos) << r1.output;
  const auto r2 = RunCmd(Arcs() + " reconstruct " + sdf + " " + (dir / "t2.ply").string() + p + " --threads 2");
  ASSERT_EQ(r2.code, 0) << r2.output;
  EXPECT_EQ(testing::ReadFile(dir / "t1.ply"), testing::ReadFile(dir / "t2.ply"))
      << "the output mesh must not depend on the thread count";
  const auto mc = RunCmd(Arcs() + " reconstruct " + sdf + " " + (dir / "mc.ply").string() + " --method marching_cubes");
  ASSERT_EQ(mc.code, 0) << mc.output;
  const auto e_rfta = RunCmd(Arcs() + " eval " + (dir / "t1.ply").string() + " shape:torus --samples 100000");
  const auto e_mc = RunCmd(Arcs() + " eval " + (dir / "mc.ply").string() + " shape:torus --samples 100000");
  const double c_rfta = Metric(e_rfta.output, "chamfer_p2s"), c_mc = Metric(e_mc.output, "chamfer_p2s");
  ASSERT_GT(c_rfta, 0) << e_rfta.output;
  EXPECT_LT(c_rfta, 0.6 * c_mc) << "RFTA should be far below MC at a coarse grid";
}

TEST(RftaE2e, BadInputGivesClearErrors) {
  const auto dir = testing::TempDir("rfta_bad");
  auto run = [&](const std::string& name, const std::string& text) {
    testing::WriteFile(dir / name, text);
    return RunCmd(Arcs() + " reconstruct " + (dir / name).string() + " " + (dir / "out.ply").string());
  };
  std::string positive, negative;
  for (int i = 0; i < 27; ++i) {
    const double x = i % 3, y = (i / 3) % 3, z = i / 9;
    positive += std::to_string(x) + " " + std::to_string(y) + " " + std::to_string(z) + " 0.5\n";
    negative += std::to_string(x) + " " + std::to_string(y) + " " + std::to_string(z) + " -0.5\n";
  }
  const auto all_pos = run("pos.txt", positive);
  EXPECT_EQ(all_pos.code, 1);
  EXPECT_NE(all_pos.output.find("sign"), std::string::npos) << all_pos.output;
  const auto all_neg = run("neg.txt", negative);
  EXPECT_EQ(all_neg.code, 1);
  EXPECT_NE(all_neg.output.find("sign"), std::string::npos) << all_neg.output;
  const auto nan = run("nan.txt", "0 0 0 0.5\n1 0 0 nan\n0 1 0 -0.2\n");
  EXPECT_EQ(nan.code, 1);
  EXPECT_NE(nan.output.find("nan.txt:2"), std::string::npos) << nan.output;
  const auto single = run("one.txt", "0 0 0 -0.5\n");
  EXPECT_EQ(single.code, 1);
  EXPECT_NE(single.output.find("arcs: error"), std::string::npos) << single.output;
  const auto ragged = run("ragged.txt", "0 0 0 -0.5\n1 0 0\n");
  EXPECT_EQ(ragged.code, 1);
  EXPECT_NE(ragged.output.find("ragged.txt:2"), std::string::npos) << ragged.output;
  // Inside and outside spheres that intersect: not an SDF. Refused on
  // request; by default a warning and the run goes on (noisy SDFs overlap).
  const std::string conflict = "0 0 0 -0.5\n0.1 0 0 0.5\n1 1 1 0.3\n0.5 0.5 0.5 -0.1\n";
  testing::WriteFile(dir / "conflict.txt", conflict);
  const auto strict = RunCmd(Arcs() + " reconstruct " + (dir / "conflict.txt").string() + " " +
                             (dir / "out.ply").string() + " --param on_sign_conflict=error");
  EXPECT_EQ(strict.code, 1);
  EXPECT_NE(strict.output.find("not a consistent SDF"), std::string::npos) << strict.output;
  const auto lenient = RunCmd(Arcs() + " reconstruct " + (dir / "conflict.txt").string() + " " +
                              (dir / "out.ply").string());
  EXPECT_NE(lenient.output.find("not a consistent SDF"), std::string::npos) << lenient.output;
  EXPECT_TRUE(lenient.code == 0 || lenient.output.find("arcs: error") != std::string::npos) << lenient.output;
  for (const auto* r : {&all_pos, &all_neg, &nan, &single, &ragged, &strict, &lenient})
    EXPECT_EQ(r->output.find("Segmentation"), std::string::npos) << r->output;
}

TEST(RftaE2e, ReducedTable1RftaBeatsMc) {
  ARCS_REQUIRE_SHARED_DATA();
  const auto dir = testing::TempDir("rfta_table1_reduced");
  const std::string cmd =
      Arcs() + " run " + ARCS_SOURCE_DIR + "/experiments/rfta_table1.yaml" + " --set 'datasets.bench.files=[" +
      testing::SharedData("tiny") + "/eight.obj, " + testing::SharedData("tiny") + "/spot.obj]'" +
      " --set 'inputs.grid.sdf_grid.n=[10, 20]'" + " --set methods.RFTA.rfta.iterations=3" +
      " --set methods.RFTA.rfta.max_points_per_sphere=3" +
      " --set 'metrics=[{stage: chamfer, params: {samples: 100000}}, hausdorff, e_sdf, topology]'" + " --out " +
      (dir / "out").string();
  const auto r = RunCmd(cmd);
  ASSERT_EQ(r.code, 0) << r.output;
  const CsvTable t = ReadCsv((dir / "out" / "results.csv").string());
  ASSERT_EQ(t.rows.size(), 8u);
  for (size_t i = 0; i < t.rows.size(); ++i) EXPECT_EQ(t.Cell(i, "status"), "ok") << t.Cell(i, "error");
  const CsvTable tab = ReadCsv((dir / "out" / "tables" / "table2_all.csv").string());
  ASSERT_EQ(tab.rows.size(), 2u);
  for (size_t i = 0; i < tab.rows.size(); ++i) {
    EXPECT_LT(std::stod(tab.Cell(i, "chamfer RFTA")), std::stod(tab.Cell(i, "chamfer MC"))) << "n = " << tab.rows[i][0];
    EXPECT_FALSE(tab.Cell(i, "chamfer RFTA (paper)").empty());
  }
}

}  // namespace
}  // namespace arcs
