// The 2D stages through the registry: sdf_grid_2d -> marching_squares / rfta
// (2D dispatch) -> chamfer_2d, hausdorff_2d, e_sdf_2d, topology_2d; and the
// 2D pipeline spelled out [rasterize, arc_projector, fine_tune,
// screened_poisson_2d] gives the same curve as `rfta`.
#include "framework/geometry/curves.h"
#include "framework/io/sdf_io.h"
#include "registry/registry.h"
#include "stages/builtin.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace arcs {
namespace {

void RunStage(const Registry& r, const std::string& name, const ParamMap& given, Context& ctx, CaseData& d) {
  r.Get(name).factory(r.Resolve(name, given))->Run(ctx, d);
}

double Metric(const CaseData& d, const std::string& name) {
  for (const auto& [k, v] : d.metrics)
    if (k == name) return v;
  ADD_FAILURE() << "no metric " << name;
  return -1;
}

CaseData StarCase(const Registry& r, int n) {
  CaseData d;
  d.registry = &r;
  Polyline c = MakeBuiltinCurve("star", 1024);
  NormalizeCurve(&c);
  d.reference_curve = c;
  Context ctx(1);
  ParamMap g;
  g.Set("n", std::int64_t{n});
  RunStage(r, "sdf_grid_2d", g, ctx, d);
  return d;
}

TEST(PlanarStages, RegisteredWithRolesAndDefaults) {
  Registry r;
  RegisterBuiltinStages(r);
  EXPECT_EQ(r.Get("sdf_grid_2d").role, Role::kSdfSampler);
  EXPECT_EQ(r.Get("sdf_random_2d").role, Role::kSdfSampler);
  EXPECT_EQ(r.Get("marching_squares").role, Role::kSdfToMesh);
  EXPECT_EQ(r.Get("screened_poisson_2d").role, Role::kReconstructor);
  for (const char* e : {"chamfer_2d", "hausdorff_2d", "e_sdf_2d", "topology_2d"})
    EXPECT_EQ(r.Get(e).role, Role::kEvaluator) << e;
  EXPECT_DOUBLE_EQ(r.Resolve("screened_poisson_2d", ParamMap()).GetDouble("screening"), 10.0);
}

TEST(PlanarStages, MarchingSquaresAndRftaOnTheStar) {
  Registry r;
  RegisterBuiltinStages(r);
  Context ctx(1);
  CaseData ms = StarCase(r, 20);
  ASSERT_EQ(ms.samples->dim, 2);
  RunStage(r, "marching_squares", ParamMap(), ctx, ms);
  ASSERT_TRUE(ms.output_curve.has_value());
  EXPECT_FALSE(ms.output.has_value());
  CaseData rf = StarCase(r, 20);
  RunStage(r, "rfta", ParamMap(), ctx, rf);
  ASSERT_TRUE(rf.output_curve.has_value()) << "rfta on 2D samples writes the output curve";
  EXPECT_FALSE(rf.output.has_value());
  for (CaseData* d : {&ms, &rf})
    for (const char* e : {"chamfer_2d", "hausdorff_2d", "e_sdf_2d", "topology_2d"}) RunStage(r, e, ParamMap(), ctx, *d);
  EXPECT_LT(Metric(rf, "chamfer_2d"), Metric(ms, "chamfer_2d"));
  EXPECT_LT(Metric(rf, "e_sdf_2d"), Metric(ms, "e_sdf_2d"));
  EXPECT_EQ(Metric(rf, "out_curve_components"), 1);
  EXPECT_EQ(Metric(rf, "out_curve_open_ends"), 0);
  EXPECT_EQ(Metric(ms, "out_curve_components"), 1);
  EXPECT_GT(Metric(rf, "rfta_points"), 0);
}

TEST(PlanarStages, ExplicitPipelineEqualsTheRftaStage) {
  Registry r;
  RegisterBuiltinStages(r);
  CaseData a = StarCase(r, 12), b = StarCase(r, 12);
  {
    Context ctx(3);
    RunStage(r, "rfta", ParamMap(), ctx, a);
  }
  {
    Context ctx(3);
    RunStage(r, "rasterize", ParamMap(), ctx, b);
    RunStage(r, "arc_projector", ParamMap(), ctx, b);
    ParamMap ft;  // the rfta stage's tuning reconstructor: the final one's 2D twin with its defaults
    StageSpec same{"screened_poisson_2d", r.Resolve("screened_poisson_2d", ParamMap())};
    ft.Set("reconstructor", std::make_shared<StageSpec>(same));
    RunStage(r, "fine_tune", ft, ctx, b);
    RunStage(r, "screened_poisson_2d", ParamMap(), ctx, b);
  }
  ASSERT_TRUE(a.output_curve && b.output_curve);
  ASSERT_EQ(a.output_curve->NumVertices(), b.output_curve->NumVertices());
  EXPECT_EQ((a.output_curve->V - b.output_curve->V).cwiseAbs().maxCoeff(), 0.0);
}

TEST(PlanarStages, TwoDimensionalSdfFilesFeedRfta) {
  // What `arcs reconstruct` reads: 2D text ('x y s') and 2D grid .npy files.
  Registry r;
  RegisterBuiltinStages(r);
  const CaseData base = StarCase(r, 10);
  const auto dir = arcs::testing::TempDir("planar_sdf_files");
  WriteSdfText((dir / "star.txt").string(), *base.samples);
  WriteSdfGrid((dir / "star.npy").string(), *base.samples);
  for (const char* f : {"star.txt", "star.npy"}) {
    CaseData d;
    d.registry = &r;
    d.samples = ReadSdf((dir / f).string());
    ASSERT_EQ(d.samples->dim, 2) << f;
    ASSERT_EQ(d.samples->Size(), base.samples->Size()) << f;
    EXPECT_EQ((d.samples->values - base.samples->values).cwiseAbs().maxCoeff(), 0.0) << f;
    Context ctx(1);
    ParamMap p;
    p.Set("iterations", std::int64_t{2});
    RunStage(r, "rfta", p, ctx, d);
    ASSERT_TRUE(d.output_curve.has_value()) << f;
    EXPECT_FALSE(d.output_curve->Empty()) << f;
  }
}

TEST(PlanarStages, ClearErrors) {
  Registry r;
  RegisterBuiltinStages(r);
  Context ctx(1);
  CaseData none;
  none.registry = &r;
  EXPECT_THROW(RunStage(r, "sdf_grid_2d", ParamMap(), ctx, none), Error);  // no reference curve
  CaseData d = StarCase(r, 10);
  EXPECT_THROW(RunStage(r, "marching_cubes", ParamMap(), ctx, d), Error);  // 2D samples
  EXPECT_THROW(RunStage(r, "chamfer_2d", ParamMap(), ctx, d), Error);      // no output curve
  d.samples->values = d.samples->values.cwiseAbs().array() + 0.01;
  EXPECT_THROW(RunStage(r, "rfta", ParamMap(), ctx, d), Error);  // all positive
  CaseData n = StarCase(r, 10);
  n.samples->values[3] = std::nan("");
  EXPECT_THROW(RunStage(r, "rfta", ParamMap(), ctx, n), Error);
  CaseData s3 = StarCase(r, 10);
  EXPECT_THROW(RunStage(r, "screened_poisson_2d", ParamMap(), ctx, s3), Error);  // no points
}

}  // namespace
}  // namespace arcs
