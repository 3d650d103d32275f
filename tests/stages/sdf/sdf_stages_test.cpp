// The SDF stages, the evaluators and the point stages through the registry,
// after their move to the parameter binder and the stage contract (issue 11):
// values the algorithms refuse are refused by Resolve (load time) with the
// stage's name once, a stage run without its declared inputs names the slot,
// and a pipeline whose point or metric stages lack their input is refused.
#include "framework/geometry/builtin_shapes.h"
#include "registry/registry.h"
#include "stages/builtin.h"

#include "tests/builtin_registry.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace arcs {
namespace {

using testing::Builtins;

// The message of Resolve(stage, {name: v}), or "" if it accepts.
template <class V>
std::string ResolveError(const std::string& stage, const std::string& name, V v) {
  ParamMap given;
  given.Set(name, v);
  try {
    Builtins().Resolve(stage, given);
  } catch (const OptionError& e) {
    return e.what();
  }
  return "";
}

std::string PipelineError(const std::vector<std::string>& stages, Slots start, int dim) {
  try {
    Builtins().CheckPipeline(stages, start, dim, [](std::size_t i) { return "exp.yaml:" + std::to_string(10 + i); });
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(SdfStages, BoxAndGridRefusedAtLoadByTheAlgorithmsCheck) {
  // hi <= lo was a run-time check of the stage; SdfGridOptions::Check() now refuses it in Resolve.
  const std::string e = ResolveError("sdf_grid", "hi", -1.0);
  EXPECT_EQ(e.rfind("sdf_grid.hi = ", 0), 0u) << e;
  EXPECT_EQ(e.find("sdf_grid.sdf_grid"), std::string::npos) << e;
  EXPECT_NE(ResolveError("sdf_random", "hi", -2.0).find("sdf_random.hi"), std::string::npos);
  EXPECT_NE(ResolveError("sdf_sweep", "hi", -1.0).find("sdf_sweep.hi"), std::string::npos);
  // n: schema and Check() both [1, 2048] (Check() said 2000 before).
  EXPECT_EQ(ResolveError("sdf_grid", "n", std::int64_t{2048}), "");
  EXPECT_NE(ResolveError("sdf_grid", "n", std::int64_t{2049}), "");
  EXPECT_EQ(ResolveError("sdf_sweep", "n", std::int64_t{2048}), "");
  // clamp: (0, inf) as ClampSdf takes it (the schema said >= 1e-12 before).
  EXPECT_EQ(ResolveError("sdf_clamp", "clamp", 1e-13), "");
  EXPECT_NE(ResolveError("sdf_clamp", "clamp", 0.0), "");
  EXPECT_NE(ResolveError("sdf_sweep", "steps", std::int64_t{1}).find("sdf_sweep.steps"), std::string::npos);
  EXPECT_NE(ResolveError("sdf_grid", "sign", std::string("nearest")), "");
}

TEST(SdfStages, GridOfASphereThroughTheRegistry) {
  const Registry& r = Builtins();
  Context ctx(3);
  CaseData d;
  d.registry = &r;
  d.reference = MakeIcosphere(0.5, 3);
  ParamMap given;
  given.Set("n", std::int64_t{4});
  given.Set("sign", std::string("exact_winding_number"));
  r.Create({"sdf_grid", r.Resolve("sdf_grid", given)})->Run(ctx, d);
  ASSERT_TRUE(d.samples);
  ASSERT_EQ(d.samples->values.size(), 125);
  // Node (2, 2, 2) is the centre: inside, at about the radius from the surface.
  const double centre = d.samples->values[2 + 5 * (2 + 5 * 2)];
  EXPECT_LT(centre, 0.0);
  EXPECT_NEAR(centre, -0.5, 0.02);
  // A corner (1, 1, 1) lies outside at |(1,1,1)| - 0.5.
  EXPECT_NEAR(d.samples->values[124], std::sqrt(3.0) - 0.5, 0.02);
}

TEST(SdfStages, RunWithoutTheDeclaredInputNamesTheSlotOnce) {
  const Registry& r = Builtins();
  Context ctx;
  for (const char* stage : {"sdf_noise", "sdf_clamp", "e_sdf"}) {
    CaseData d;
    d.registry = &r;
    d.output = MakeIcosphere(0.5, 1);
    try {
      r.Create({stage, r.Resolve(stage, ParamMap{})})->Run(ctx, d);
      FAIL() << stage << " ran without samples";
    } catch (const Error& e) {
      const std::string m = e.what();
      EXPECT_EQ(m.rfind(std::string(stage) + ": needs samples", 0), 0u) << m;
      EXPECT_NE(m.find("sdf_grid"), std::string::npos) << m;  // a stage that writes samples
    }
  }
  CaseData d;
  d.registry = &r;
  d.reference = MakeIcosphere(0.5, 1);
  try {
    r.Create({"chamfer", r.Resolve("chamfer", ParamMap{})})->Run(ctx, d);
    FAIL() << "chamfer ran without an output";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("chamfer: needs output", 0), 0u) << e.what();
  }
}

TEST(SdfStages, PointAndMetricPipelinesAreCheckedAtLoad) {
  EXPECT_EQ(PipelineError({"sample_surface", "estimate_normals", "graph_voronoi", "chamfer", "topology"},
                          Slots{Slot::kReference}, 3),
            "");
  const std::string e = PipelineError({"graph_voronoi", "chamfer"}, Slots{Slot::kReference}, 3);
  EXPECT_NE(e.find("exp.yaml:10: stage 'graph_voronoi' needs points"), std::string::npos) << e;
  EXPECT_NE(e.find("sample_surface"), std::string::npos) << e;
  const std::string m = PipelineError({"sdf_grid", "chamfer"}, Slots{Slot::kReference}, 3);
  EXPECT_NE(m.find("exp.yaml:11: stage 'chamfer' needs output"), std::string::npos) << m;
  // The 3D evaluators refuse a 2D case.
  const std::string d2 = PipelineError({"chamfer"}, Slots{Slot::kReference, Slot::kOutput}, 2);
  EXPECT_NE(d2.find("chamfer"), std::string::npos) << d2;
  EXPECT_NE(d2.find("3D"), std::string::npos) << d2;
}

TEST(SdfStages, PointStagesRefuseBadValuesAtLoad) {
  EXPECT_NE(ResolveError("ball_pivoting", "radius", 2e30), "");
  EXPECT_NE(ResolveError("graph_voronoi", "outlier_ratio", 0.5).find("graph_voronoi.outlier_ratio"),
            std::string::npos);
  EXPECT_EQ(ResolveError("graph_voronoi", "vertex_position", std::string("cell_mean")), "");
  ParamMap fr;
  fr.Set("full_resolution", true);
  fr.Set("triangulate", false);
  EXPECT_THROW(Builtins().Resolve("graph_voronoi", fr), OptionError);
  EXPECT_NE(ResolveError("chamfer", "samples", std::int64_t{0}), "");
}

}  // namespace
}  // namespace arcs
