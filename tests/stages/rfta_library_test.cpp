// One Reach for the Arcs for both dimensions: the library's ReachForTheArcs
// with its default sampler and reconstructors gives bit for bit the surface
// and points of the `rfta` stage with its defaults (registered nested stages),
// in 3D (torus, n = 10) and 2D (star, n = 12); the stage writes each part's
// metrics; a reconstructor of the wrong dimension is a clear error.
#include "framework/error.h"
#include "framework/eval/metrics.h"
#include "framework/io/mesh_io.h"
#include "framework/geometry/builtin_shapes.h"
#include "framework/geometry/curves.h"
#include "framework/geometry/normalize.h"
#include "framework/rfta/reach_for_the_arcs.h"
#include "framework/sdf/sdf2d.h"
#include "framework/sdf/sdf_sampling.h"
#include "registry/registry.h"
#include "stages/builtin.h"
#include "stages/reconstruct/screened_poisson_spec.h"

#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <variant>
#include <vector>

namespace arcs {
namespace {

// Runs the registered rfta stage; `warnings` (optional) receives what it warned.
CaseData RunRftaStage(const Registry& r, const SdfSamples& samples, const ParamMap& given, std::uint64_t seed,
                      std::vector<std::string>* warnings = nullptr) {
  CaseData d;
  d.registry = &r;
  d.samples = samples;
  Context ctx(seed);
  if (warnings)
    ctx.set_log([warnings](LogLevel level, const std::string& msg) {
      if (level == LogLevel::kWarning) warnings->push_back(msg);
    });
  r.Get("rfta").factory(r.Resolve("rfta", given))->Run(ctx, d);
  return d;
}

bool Has(const CaseData& d, const std::string& name) {
  for (const auto& [k, v] : d.metrics)
    if (k == name) return true;
  return false;
}

// The normalised torus's exact SDF on the 11^3 nodes of [-1, 1]^3.
SdfSamples TorusSamples10() {
  Mesh torus = MakeTorus();
  Normalize(&torus, NormalizeOptions{});
  SdfGridOptions go;
  go.n = 10;
  return SampleSdfGrid(torus, go, Context(1));
}

TEST(RftaLibrary, DefaultsEqualTheStageIn3D) {
  const SdfSamples s = TorusSamples10();
  Registry r;
  RegisterBuiltinStages(r);
  ParamMap given;
  given.Set("iterations", std::int64_t{3});
  const CaseData d = RunRftaStage(r, s, given, 5);
  RftaOptions o;
  o.fine_tune.iterations = 3;
  const RftaResult lib = ReachForTheArcs(s, o, Context(5));
  ASSERT_TRUE(d.output.has_value());
  ASSERT_TRUE(std::holds_alternative<Mesh>(lib.surface));
  const Mesh& m = std::get<Mesh>(lib.surface);
  ASSERT_GT(m.NumFaces(), 0);
  ASSERT_EQ(m.NumVertices(), d.output->NumVertices());
  ASSERT_EQ(m.NumFaces(), d.output->NumFaces());
  EXPECT_EQ((m.V - d.output->V).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((m.F - d.output->F).cwiseAbs().maxCoeff(), 0);
  ASSERT_EQ(lib.points.Size(), d.points->Size());
  EXPECT_EQ((lib.points.P - d.points->P).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(lib.sample, d.point_sample);
  EXPECT_EQ(lib.tuning.iterations.size(), 3u);
  for (const char* k : {"rfta_sign_conflicts", "raster_resolution", "free_points", "rfta_sampler_s", "arc_points",
                        "arc_dropped", "rfta_projector_s", "rfta_points", "fine_tune_iterations",
                        "fine_tune_reconstruct_s", "rfta_fine_tune_s", "poisson_depth", "rfta_final_s"})
    EXPECT_TRUE(Has(d, k)) << k;
}

// The deepest that a vertex of m enters an outside sample's ball (s - |v - p|
// over the samples with s > 0; negative: no vertex enters any).
double DeepestEntry(const Mesh& m, const SdfSamples& s) {
  double deepest = -1e300;
  for (int v = 0; v < m.NumVertices(); ++v)
    for (std::int64_t i = 0; i < s.Size(); ++i)
      if (s.values[i] > 0)
        deepest = std::max(deepest, s.values[i] - (Vec3(m.V.row(v)) - Vec3(s.points.row(i).head<3>())).norm());
  return deepest;
}

TEST(RftaLibrary, CarvingLeavesNoVertexInsideAnOutsideBall) {
  // Torus, n = 10: the same points reconstructed with and without carving
  // (the final surface is the only difference). Carved, no vertex enters a
  // ball by more than the margin (carve_margin x h, h = 0.2) and the edges'
  // chord error (under 10^-3 here); the library and the stage carve alike;
  // carving never raises E_SDF here.
  const SdfSamples s = TorusSamples10();
  Registry r;
  RegisterBuiltinStages(r);
  ParamMap given;
  given.Set("iterations", std::int64_t{3});
  const CaseData carved = RunRftaStage(r, s, given, 5);
  given.Set("carve", false);
  const CaseData plain = RunRftaStage(r, s, given, 5);
  ASSERT_TRUE(carved.output && plain.output);
  ASSERT_EQ(carved.points->Size(), plain.points->Size());
  EXPECT_EQ((carved.points->P - plain.points->P).cwiseAbs().maxCoeff(), 0.0);
  const double plain_depth = DeepestEntry(*plain.output, s), carved_depth = DeepestEntry(*carved.output, s);
  std::printf("deepest entry into an outside ball: %.3g without carving, %.3g with\n", plain_depth, carved_depth);
  const double margin = RftaOptions{}.carve_margin * 0.2;
  EXPECT_GT(plain_depth, margin + 1e-2) << "nothing to carve: this test shows nothing";
  EXPECT_LT(carved_depth, margin + 1e-3);
  EXPECT_LE(EnergySdf(s, *carved.output), EnergySdf(s, *plain.output) * (1 + 1e-9));
  RftaOptions o;
  o.fine_tune.iterations = 3;
  const Mesh lib = std::get<Mesh>(ReachForTheArcs(s, o, Context(5)).surface);
  ASSERT_EQ(lib.NumVertices(), carved.output->NumVertices());
  EXPECT_EQ((lib.V - carved.output->V).cwiseAbs().maxCoeff(), 0.0);
}

TEST(RftaLibrary, CarvingRemovesTheSheetAcrossAHollowTube) {
  // thingi37358 (a hollow lattice tube) at n = 10, paper preset: without
  // carving the surface through the tangency points spans the tube's hollow
  // inside the balls of the samples on its axis (E_SDF 0.5 and more, session
  // 41); carved, the hollow is empty again.
  ARCS_REQUIRE_SHARED_DATA();
  Mesh ref = ReadMesh(testing::SharedData("bench/thingi37358_sf.obj"));
  Normalize(&ref, NormalizeOptions{});
  SdfGridOptions go;
  go.n = 10;
  const SdfSamples s = SampleSdfGrid(ref, go, Context(1));
  Registry r;
  RegisterBuiltinStages(r);
  ParamMap given;
  given.Set("iterations", std::int64_t{20});
  given.Set("max_points_per_sphere", std::int64_t{30});
  const CaseData carved = RunRftaStage(r, s, given, 1);
  given.Set("carve", false);
  const CaseData plain = RunRftaStage(r, s, given, 1);
  const double e_carved = EnergySdf(s, *carved.output), e_plain = EnergySdf(s, *plain.output);
  std::printf("thingi37358 n = 10: E_SDF %.4f without carving, %.4f with\n", e_plain, e_carved);
  EXPECT_GT(e_plain, 0.1);
  EXPECT_LT(e_carved, 0.01);
}

TEST(RftaLibrary, SampleSpacingOfGridsAndScatteredSamples) {
  EXPECT_DOUBLE_EQ(SampleSpacing(TorusSamples10()), 0.2);  // linspace(-1, 1, 11)
  SdfSamples s;  // no grid: the median nearest-other-sample distance
  s.points = MatrixXd::Zero(5, 3);
  s.points.col(0) << 0.0, 0.1, 0.2, 0.5, 0.5;  // a duplicate does not count as its own neighbour at 0
  s.values = VectorXd::Constant(5, 0.1);
  EXPECT_NEAR(SampleSpacing(s), 0.1, 1e-12);
  s.points = MatrixXd::Zero(1, 3);
  s.values = VectorXd::Constant(1, 0.1);
  EXPECT_EQ(SampleSpacing(s), 0.0);
}

TEST(RftaLibrary, TuningCellCoarsensTheTuningSurfacesInStageAndLibraryAlike) {
  const SdfSamples s = TorusSamples10();
  Registry r;
  RegisterBuiltinStages(r);
  ParamMap given;
  given.Set("iterations", std::int64_t{3});
  given.Set("tuning_cell", 0.6);
  const CaseData d = RunRftaStage(r, s, given, 5);
  ASSERT_TRUE(Has(d, "rfta_tuning_max_cell"));
  for (const auto& [k, v] : d.metrics) {
    if (k == "rfta_tuning_max_cell") {
      EXPECT_NEAR(v, 0.6 * 0.2, 1e-12);
    }
  }
  RftaOptions o;
  o.fine_tune.iterations = 3;
  const RftaResult plain = ReachForTheArcs(s, o, Context(5));
  o.tuning_cell = 0.6;
  const RftaResult lib = ReachForTheArcs(s, o, Context(5));
  ASSERT_TRUE(d.output.has_value());
  const Mesh& m = std::get<Mesh>(lib.surface);
  ASSERT_EQ(m.NumVertices(), d.output->NumVertices());
  EXPECT_EQ((m.V - d.output->V).cwiseAbs().maxCoeff(), 0.0);
  ASSERT_EQ(lib.points.Size(), d.points->Size());
  EXPECT_EQ((lib.points.P - d.points->P).cwiseAbs().maxCoeff(), 0.0);
  // Coarser tuning surfaces (cells 0.12 against about 0.025) move the points differently.
  EXPECT_TRUE(plain.points.Size() != lib.points.Size() ||
              (plain.points.P - lib.points.P).cwiseAbs().maxCoeff() > 0.0);
  o.tuning_cell = -1;
  EXPECT_THROW(ReachForTheArcs(s, o, Context(5)), OptionError);
}

// pair_choice reaches Algorithm 2 in the projector and in the fine-tuner, in
// the stage as in the library; its default is the one arc_projector and
// fine_tune declare (one declaration), the paper's closest candidate.
TEST(RftaLibrary, PairChoiceReachesProjectorAndFineTunerInStageAndLibraryAlike) {
  const SdfSamples s = TorusSamples10();
  Registry r;
  RegisterBuiltinStages(r);
  const std::string def = r.Resolve("rfta", ParamMap()).GetString("pair_choice");
  EXPECT_EQ(def, "closest");
  EXPECT_EQ(r.Resolve("arc_projector", ParamMap()).GetString("pair_choice"), def);
  EXPECT_EQ(r.Resolve("fine_tune", ParamMap()).GetString("pair_choice"), def);
  ParamMap given;
  given.Set("iterations", std::int64_t{3});
  given.Set("pair_choice", std::string("first"));
  const CaseData d = RunRftaStage(r, s, given, 5);
  RftaOptions o;
  o.fine_tune.iterations = 3;
  const RftaResult closest = ReachForTheArcs(s, o, Context(5));
  o.projector.search.pair_choice = o.fine_tune.search.pair_choice = PairChoice::kFirst;
  const RftaResult lib = ReachForTheArcs(s, o, Context(5));
  ASSERT_TRUE(d.points.has_value());
  ASSERT_EQ(lib.points.Size(), d.points->Size());
  EXPECT_EQ((lib.points.P - d.points->P).cwiseAbs().maxCoeff(), 0.0);
  // The rule decides where Algorithm 2 puts points, so the clouds differ.
  EXPECT_TRUE(closest.points.Size() != lib.points.Size() ||
              (closest.points.P - lib.points.P).cwiseAbs().maxCoeff() > 0.0);
  given.Set("pair_choice", std::string("nearest"));
  EXPECT_THROW(r.Resolve("rfta", given), OptionError);
}

// tuning_cell where it cannot apply (the tuning screened_poisson's own
// extract_max_cell already set) is said in a warning, not silently ignored,
// and leaves the nested stage's value.
TEST(RftaLibrary, TuningCellThatCannotApplyIsAWarning) {
  const SdfSamples s = TorusSamples10();
  Registry r;
  RegisterBuiltinStages(r);
  ParamMap given;
  given.Set("iterations", std::int64_t{1});
  given.Set("tuning_cell", 0.6);
  auto tuning = std::make_shared<StageSpec>(RftaTuningPoissonSpec());
  tuning->params.Set("extract_max_cell", 0.05);
  given.Set("tuning_reconstructor", tuning);
  std::vector<std::string> warnings;
  const CaseData d = RunRftaStage(r, s, given, 5, &warnings);
  EXPECT_FALSE(Has(d, "rfta_tuning_max_cell"));
  bool said = false;
  for (const std::string& w : warnings) said = said || w.find("tuning_cell 0.6") != std::string::npos;
  EXPECT_TRUE(said) << "no warning about tuning_cell among " << warnings.size();
}

TEST(RftaLibrary, DefaultsEqualTheStageIn2D) {
  Polyline c = MakeBuiltinCurve("star", 1024);
  NormalizeCurve(&c);
  SdfGrid2DOptions go;
  go.n = 12;
  const SdfSamples s = SampleSdfGrid2D(c, go, Context(1));
  Registry r;
  RegisterBuiltinStages(r);
  const CaseData d = RunRftaStage(r, s, ParamMap(), 3);
  const RftaResult lib = ReachForTheArcs(s, RftaOptions{}, Context(3));
  ASSERT_TRUE(d.output_curve.has_value());
  EXPECT_FALSE(d.output.has_value());
  ASSERT_TRUE(std::holds_alternative<Polyline>(lib.surface));
  const Polyline& curve = std::get<Polyline>(lib.surface);
  ASSERT_GT(curve.NumVertices(), 0);
  ASSERT_EQ(curve.NumVertices(), d.output_curve->NumVertices());
  EXPECT_EQ((curve.V - d.output_curve->V).cwiseAbs().maxCoeff(), 0.0);
  ASSERT_EQ(curve.NumEdges(), d.output_curve->NumEdges());
  EXPECT_EQ((curve.E - d.output_curve->E).cwiseAbs().maxCoeff(), 0);
  ASSERT_EQ(lib.points.Size(), d.points->Size());
  EXPECT_EQ((lib.points.P - d.points->P).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_TRUE(Has(d, "poisson2d_resolution"));
  EXPECT_TRUE(Has(d, "rfta_final_s"));
}

TEST(RftaLibrary, ReconstructorOfTheOtherDimensionIsAClearError) {
  Polyline c = MakeBuiltinCurve("circle", 512);
  SdfGrid2DOptions go;
  go.n = 8;
  const SdfSamples s = SampleSdfGrid2D(c, go, Context(1));
  RftaParts parts;
  int calls = 0;
  parts.reconstruct = [&](const PointCloud&) -> Surface {
    ++calls;
    return Mesh();
  };
  RftaOptions o;
  o.fine_tune.iterations = 1;
  try {
    ReachForTheArcs(s, o, parts, Context(1));
    ADD_FAILURE() << "a mesh for 2D samples was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("gave a mesh for 2D samples"), std::string::npos) << e.what();
  }
  EXPECT_EQ(calls, 1);
  // Every part reports once, in order.
  std::vector<RftaPart> seen;
  parts = RftaParts{};
  parts.after = [&](RftaPart p, const RftaResult&) { seen.push_back(p); };
  ReachForTheArcs(s, o, parts, Context(1));
  EXPECT_EQ(seen, (std::vector<RftaPart>{RftaPart::kSignCheck, RftaPart::kSampler, RftaPart::kProjector,
                                          RftaPart::kFineTune, RftaPart::kFinal}));
}

}  // namespace
}  // namespace arcs
