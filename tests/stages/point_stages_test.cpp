// The point-cloud stages through the registry, as an experiment composes
// them: sample_surface -> (estimate_normals) -> each reconstructor, and a
// reconstructor as RFTA's nested `reconstructor` parameter.
#include "framework/geometry/builtin_shapes.h"
#include "framework/spatial/topology.h"
#include "registry/registry.h"
#include "stages/builtin.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

namespace arcs {
namespace {

void RunStage(const Registry& r, const std::string& name, const ParamMap& given, Context& ctx, CaseData& d) {
  r.Get(name).factory(r.Resolve(name, given))->Run(ctx, d);
}

TEST(PointStages, RolesAndDefaults) {
  Registry r;
  RegisterBuiltinStages(r);
  for (const char* s : {"ball_pivoting", "alpha_shape", "advancing_front", "screened_poisson"})
    EXPECT_EQ(r.Get(s).role, Role::kReconstructor) << s;
  EXPECT_EQ(r.Get("sample_surface").role, Role::kPointSampler);
  EXPECT_EQ(r.Get("estimate_normals").role, Role::kPointModifier);
  EXPECT_EQ(r.Get("subsample_points").role, Role::kPointModifier);
}

TEST(PointStages, SampledSphereThroughEveryReconstructor) {
  Registry r;
  RegisterBuiltinStages(r);
  Context ctx(5);
  CaseData base;
  base.registry = &r;
  base.reference = MakeIcosphere(0.5, 4);
  ParamMap n;
  n.Set("count", std::int64_t{3000});
  RunStage(r, "sample_surface", n, ctx, base);
  ASSERT_EQ(base.points->Size(), 3000);
  // Same seed, same points.
  CaseData again = base;
  RunStage(r, "sample_surface", n, ctx, again);
  EXPECT_EQ(again.points->P, base.points->P);
  // Drop the exact normals and estimate them: all outward.
  base.points->N.resize(0, 3);
  try {
    CaseData d = base;
    RunStage(r, "ball_pivoting", {}, ctx, d);
    FAIL() << "ball pivoting without normals must fail";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("estimate_normals"), std::string::npos) << e.what();
  }
  RunStage(r, "estimate_normals", {}, ctx, base);
  ASSERT_TRUE(base.points->HasNormals());
  int inward = 0;
  for (int i = 0; i < base.points->Size(); ++i) inward += base.points->N.row(i).dot(base.points->P.row(i)) < 0;
  EXPECT_EQ(inward, 0);
  for (const char* s : {"alpha_shape", "advancing_front", "ball_pivoting", "screened_poisson"}) {
    CaseData d = base;
    RunStage(r, s, {}, ctx, d);
    ASSERT_TRUE(d.output) << s;
    const Topology t = ComputeTopology(*d.output);
    EXPECT_GT(t.volume, 0.9 * 4.0 / 3.0 * M_PI * 0.125 * (t.closed ? 1 : 0)) << s;
    EXPECT_NEAR(t.area, M_PI, 0.05 * M_PI) << s;
  }
}

TEST(PointStages, ReconstructorAsRftaParameter) {
  // The SDF of a sphere on a coarse grid; RFTA's final surface by alpha shapes.
  Registry r;
  RegisterBuiltinStages(r);
  Context ctx(1);
  CaseData d;
  d.registry = &r;
  d.reference = MakeIcosphere(0.5, 3);
  ParamMap g;
  g.Set("n", std::int64_t{12});
  RunStage(r, "sdf_grid", g, ctx, d);
  ParamMap p;
  auto spec = std::make_shared<StageSpec>();
  spec->stage = "alpha_shape";
  spec->params = r.Resolve("alpha_shape", {});
  p.Set("reconstructor", spec);
  p.Set("iterations", std::int64_t{1});
  RunStage(r, "rfta", p, ctx, d);
  ASSERT_TRUE(d.output);
  const Topology t = ComputeTopology(*d.output);
  EXPECT_TRUE(t.closed);
  EXPECT_EQ(t.genus, 0);
}

}  // namespace
}  // namespace arcs
