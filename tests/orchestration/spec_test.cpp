#include "orchestration/expand.h"
#include "orchestration/spec.h"
#include "stages/builtin.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <set>

namespace arcs {
namespace {

class ExperimentTest : public ::testing::Test {
 protected:
  void SetUp() override {
    RegisterBuiltinStages(registry_);
    dir_ = testing::TempDir(::testing::UnitTest::GetInstance()->current_test_info()->name());
  }
  std::string Write(const std::string& text) {
    const std::string path = (dir_ / "exp.yaml").string();
    std::ofstream(path) << text;
    return path;
  }
  // Expects LoadExperiment to fail with a message containing every piece.
  void ExpectError(const std::string& yaml, const std::vector<std::string>& pieces,
                   const std::vector<std::string>& overrides = {}) {
    const std::string path = Write(yaml);
    try {
      LoadExperiment(path, overrides, registry_);
      FAIL() << "expected an error for:\n" << yaml;
    } catch (const ExperimentError& e) {
      const std::string msg = e.what();
      for (const auto& p : pieces) EXPECT_NE(msg.find(p), std::string::npos) << "missing '" << p << "' in: " << msg;
    }
  }
  Registry registry_;
  std::filesystem::path dir_;
};

const char* kGood = R"(name: t
seed: 3
datasets:
  - name: shapes
    shapes: [sphere, torus]
inputs:
  - name: grid
    pipeline:
      - stage: sdf_grid
        params: {n: [6, 10, 20]}
methods:
  - name: MC
    pipeline: [marching_cubes]
  - name: MC_shifted
    pipeline:
      - stage: marching_cubes
        params: {level: [0.0, 0.01]}
metrics: [chamfer, hausdorff]
tables:
  - name: t2
    metrics: [chamfer]
    rows: n
)";

TEST_F(ExperimentTest, SweepsExpandToTheCartesianProduct) {
  const Experiment exp = LoadExperiment(Write(kGood), {}, registry_);
  const auto cases = ExpandCases(exp, registry_);
  // 2 shapes x 3 resolutions x (1 + 2) method variants.
  EXPECT_EQ(cases.size(), 2u * 3u * 3u);
  std::set<std::string> ids;
  for (const auto& c : cases) ids.insert(c.id);
  EXPECT_EQ(ids.size(), cases.size()) << "case ids must be distinct";
  // Stable: the same file expands to the same ids.
  const auto again = ExpandCases(LoadExperiment(Write(kGood), {}, registry_), registry_);
  for (size_t i = 0; i < cases.size(); ++i) EXPECT_EQ(cases[i].id, again[i].id);
  // Resolved parameters are columns.
  bool found = false;
  for (const auto& [k, v] : cases[0].params) found |= k == "sdf_grid.n" && v == "6";
  EXPECT_TRUE(found);
}

TEST_F(ExperimentTest, OverridesChangeParametersAndCases) {
  const Experiment exp = LoadExperiment(Write(kGood), {"inputs.grid.sdf_grid.n=[8]", "seed=9"}, registry_);
  const auto cases = ExpandCases(exp, registry_);
  EXPECT_EQ(cases.size(), 2u * 1u * 3u);
  EXPECT_EQ(exp.seed, 9u);
  for (const auto& c : cases) EXPECT_EQ(c.input_stages[0].params.GetInt("n"), 8);
  // A method's stage parameter through the pipeline.
  const Experiment e2 = LoadExperiment(Write(kGood), {"methods.MC.marching_cubes.level=0.05"}, registry_);
  EXPECT_DOUBLE_EQ(ExpandCases(e2, registry_)[0].method_stages[0].params.GetDouble("level"), 0.05);
}

// A nested stage named like its parameter's default starts from the default
// call (rfta's reconstructors: the official screened Poisson), the given keys
// on top; another stage, or a parameter left out, as before. The same rule
// for the YAML path and for programmatic parameters (Registry::Resolve).
// A varying nested stage is labelled by what varies in it, not by its whole
// resolved call (screened_poisson's is some 300 characters): the progress line
// and --save-outputs' file names stay readable.
TEST_F(ExperimentTest, LabelsShowOnlyTheNestedParametersThatVary) {
  const std::string yaml = R"(name: t
datasets:
  - name: shapes
    shapes: [sphere]
inputs:
  - name: grid
    pipeline: [{stage: sdf_grid, params: {n: 10}}]
methods:
  - name: RFTA
    pipeline:
      - stage: rfta
        params:
          iterations: [2, 3]
          reconstructor:
            - {stage: screened_poisson, params: {point_weight: 4}}
            - screened_poisson
            - ball_pivoting
metrics: [chamfer]
)";
  const auto cases = ExpandCases(LoadExperiment(Write(yaml), {}, registry_), registry_);
  ASSERT_EQ(cases.size(), 6u);
  std::set<std::string> labels;
  for (const auto& c : cases) {
    const std::string l = c.Label();
    labels.insert(l);
    EXPECT_LT(l.size(), 160u) << l;
    EXPECT_EQ(l.find("samples_per_node"), std::string::npos) << l;  // the same in both screened_poisson calls
  }
  EXPECT_EQ(labels.size(), cases.size()) << "every case keeps a label of its own";
  auto has = [&](const std::string& piece) {
    return std::any_of(labels.begin(), labels.end(), [&](const std::string& l) { return l.find(piece) != std::string::npos; });
  };
  EXPECT_TRUE(has("reconstructor=screened_poisson(point_weight=4"));
  EXPECT_TRUE(has("reconstructor=screened_poisson(point_weight=15"));  // the default's (the official call in full)
  EXPECT_TRUE(has("reconstructor=ball_pivoting |"));
  EXPECT_TRUE(has("iterations=3"));
}

TEST_F(ExperimentTest, NestedStageOfTheDefaultsNameInheritsTheDefaultCall) {
  const std::string yaml = R"(name: t
datasets:
  - name: shapes
    shapes: [sphere]
inputs:
  - name: grid
    pipeline: [{stage: sdf_grid, params: {n: 10}}]
methods:
  - name: RFTA
    pipeline:
      - stage: rfta
        params:
          reconstructor:
            - {stage: screened_poisson, params: {point_weight: 4}}
            - screened_poisson
            - ball_pivoting
          tuning_reconstructor: {stage: screened_poisson, params: {cg_iters: 20}}
metrics: [chamfer]
)";
  const auto cases = ExpandCases(LoadExperiment(Write(yaml), {}, registry_), registry_);
  ASSERT_EQ(cases.size(), 3u);
  const ParamMap& defaults = registry_.Resolve("rfta", ParamMap{});
  const StageSpec& official = defaults.GetStage("reconstructor");
  ASSERT_EQ(official.stage, "screened_poisson");
  EXPECT_EQ(official.params.GetString("backend"), "arcs");
  auto reconstructor = [&](std::size_t i) -> const StageSpec& {
    return cases[i].method_stages[0].params.GetStage("reconstructor");
  };
  // Weight 4 over the official call: its backend, depth, scale, normalisation.
  EXPECT_DOUBLE_EQ(reconstructor(0).params.GetDouble("point_weight"), 4.0);
  for (const char* k : {"backend", "area_normalized", "depth", "scale"})
    EXPECT_EQ(FormatParamValue(reconstructor(0).params.Get(k)), FormatParamValue(official.params.Get(k))) << k;
  // The bare name is the official call itself.
  for (const auto& [k, v] : official.params.items())
    EXPECT_EQ(FormatParamValue(reconstructor(1).params.Get(k)), FormatParamValue(v)) << k;
  // Another stage: its own defaults.
  EXPECT_EQ(reconstructor(2).stage, "ball_pivoting");
  const StageSpec& tuning = cases[0].method_stages[0].params.GetStage("tuning_reconstructor");
  EXPECT_EQ(tuning.params.GetInt("cg_iters"), 20);
  EXPECT_EQ(tuning.params.GetString("backend"), "arcs");
  // The tuning surfaces' own default call (RftaTuningPoisson, session 39), not the final one's.
  const StageSpec& tuning_default = defaults.GetStage("tuning_reconstructor");
  for (const char* k : {"point_weight", "normal_splat", "density_scale", "depth", "scale"})
    EXPECT_EQ(FormatParamValue(tuning.params.Get(k)), FormatParamValue(tuning_default.params.Get(k))) << k;
  EXPECT_NE(tuning_default.params.GetDouble("point_weight"), official.params.GetDouble("point_weight"));
  // screened_poisson's own default backend differs, so the test tells the rules apart.
  EXPECT_NE(registry_.Resolve("screened_poisson", ParamMap{}).GetString("backend"), "arcs");
  // Programmatic parameters (the CLI's --param, Python): a bare stage name.
  ParamMap given;
  auto bare = std::make_shared<StageSpec>();
  bare->stage = "screened_poisson";
  given.Set("reconstructor", bare);
  const ParamMap r = registry_.Resolve("rfta", given);
  for (const auto& [k, v] : official.params.items())
    EXPECT_EQ(FormatParamValue(r.GetStage("reconstructor").params.Get(k)), FormatParamValue(v)) << k;
}

TEST_F(ExperimentTest, ErrorsNameFileLineAndField) {
  // Unknown top-level key, with suggestion.
  ExpectError("name: t\ndatasetz: []\n", {"exp.yaml:2", "unknown key 'datasetz'", "did you mean 'datasets'"});
  // Unknown stage with suggestion.
  ExpectError(
      "datasets: [{shapes: [sphere]}]\nmethods:\n  - name: m\n    pipeline: [marching_cube]\n",
      {"exp.yaml:4", "methods[0].pipeline[0]", "unknown stage 'marching_cube'", "did you mean 'marching_cubes'"});
  // Wrong type.
  ExpectError(
      "datasets: [{shapes: [sphere]}]\ninputs:\n  - pipeline:\n      - stage: sdf_grid\n        params: {n: abc}\n"
      "methods: [{pipeline: [marching_cubes]}]\n",
      {"exp.yaml:5", "inputs[0].pipeline[0].params.n", "must be an integer"});
  // Out of range, with the allowed range.
  ExpectError(
      "datasets: [{shapes: [sphere]}]\ninputs:\n  - pipeline:\n      - stage: sdf_grid\n        params:\n"
      "          n: 0\nmethods: [{pipeline: [marching_cubes]}]\n",
      {"exp.yaml:6", "params.n", "out of range [1, 2048]"});
  // Unknown parameter.
  ExpectError(
      "datasets: [{shapes: [sphere]}]\nmethods:\n  - pipeline:\n      - stage: marching_cubes\n        params: {levle: 1}\n",
      {"exp.yaml:5", "no parameter 'levle'", "did you mean 'level'"});
  // Missing files.
  ExpectError("datasets:\n  - files: [does_not_exist/*.obj]\nmethods: [{pipeline: [marching_cubes]}]\n",
              {"exp.yaml:2", "datasets[0].files", "matches no file"});
  // A stage in the wrong role.
  ExpectError("datasets: [{shapes: [sphere]}]\nmethods: [{pipeline: [marching_cubes]}]\nmetrics: [sdf_grid]\n",
              {"exp.yaml:3", "metrics[0]", "evaluator"});
  // YAML syntax error: one line with file:line.
  ExpectError("name: t\ndatasets: [\n  - foo: : :\n", {"exp.yaml:", "YAML syntax error"});
  // Missing methods.
  ExpectError("datasets: [{shapes: [sphere]}]\n", {"methods", "missing"});
  // Bad override value location.
  ExpectError(kGood, {"--set", "params.n", "must be an integer"}, {"inputs.grid.sdf_grid.n=[x]"});
}

}  // namespace
}  // namespace arcs

namespace arcs {
namespace {

// Issue 11: what an algorithm refuses is refused at load, with FILE:LINE,
// and so is a pipeline whose stages cannot feed each other.
constexpr const char* kRftaPipeline = R"(name: contract
datasets:
  - name: s
    shapes: [sphere]
inputs:
  - name: grid
    pipeline:
      - stage: sdf_grid
        params: {n: 10}
methods:
  - name: RFTA
    pipeline:
      - rasterize
      - stage: arc_projector
        params: {tol: TOL}
      - screened_poisson
metrics: [chamfer]
)";

std::string With(std::string text, const std::string& from, const std::string& to) {
  text.replace(text.find(from), from.size(), to);
  return text;
}

TEST_F(ExperimentTest, ArcProjectorTolAtItsOpenEndIsRefusedAtLoad) {
  ExpectError(With(kRftaPipeline, "TOL", "0.1"), {"exp.yaml:15:", "params.tol", "tol = 0.1", "[0, 0.1)"});
  EXPECT_NO_THROW(LoadExperiment(Write(With(kRftaPipeline, "TOL", "0.05")), {}, registry_));
}

TEST_F(ExperimentTest, PipelineThatCannotFeedAStageIsRefusedAtLoad) {
  const std::string no_sampler = With(With(kRftaPipeline, "TOL", "0.001"), "      - rasterize\n", "");
  ExpectError(no_sampler, {"exp.yaml:13:", "stage 'arc_projector' needs free_points", "rasterize", "method 'RFTA'"});
  // A 3D mesher on a 2D dataset: the dimension is part of the contract.
  ExpectError(R"(name: dims
datasets:
  - name: c
    kind: curves
    shapes: [circle]
inputs:
  - name: grid
    pipeline:
      - stage: sdf_grid_2d
        params: {n: 10}
methods:
  - name: MC
    pipeline: [marching_cubes]
)",
              {"exp.yaml:13:", "stage 'marching_cubes' works on 3D data", "2D"});
}

}  // namespace
}  // namespace arcs
