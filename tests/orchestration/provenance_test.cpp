// The saved config.resolved.yaml (orchestration/provenance.h) is an
// experiment file again: loading it gives the same cases, and running it
// gives the same results, for every kind of dataset item (mesh files,
// built-in shapes, curve files, built-in curves).
#include "orchestration/provenance.h"

#include "framework/geometry/builtin_shapes.h"
#include "framework/io/mesh_io.h"
#include "framework/geometry/curves.h"
#include "orchestration/csv.h"
#include "orchestration/runner.h"
#include "stages/builtin.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <fstream>
#include <map>

namespace arcs {
namespace {

namespace fs = std::filesystem;

class ProvenanceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    RegisterBuiltinStages(registry_);
    dir_ = testing::TempDir(std::string("provenance_") +
                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
  }
  Experiment Load(const std::string& yaml) {
    const std::string path = (dir_ / "exp.yaml").string();
    std::ofstream(path) << yaml;
    return LoadExperiment(path, {}, registry_);
  }
  // Runs `exp` in this process into dir_/out; returns case id -> its row.
  std::map<std::string, std::map<std::string, std::string>> Run(const Experiment& exp, const std::string& out) {
    RunOptions o;
    o.out_dir = (dir_ / out).string();
    o.isolate = false;
    o.progress = false;
    o.threads = 1;
    const RunSummary s = RunExperiment(exp, registry_, o);
    EXPECT_EQ(s.failed, 0);
    const CsvTable t = ReadCsv((dir_ / out / "results.csv").string());
    std::map<std::string, std::map<std::string, std::string>> rows;
    for (size_t r = 0; r < t.rows.size(); ++r)
      for (size_t c = 0; c < t.header.size(); ++c) rows[t.Cell(r, "case_id")][t.header[c]] = t.rows[r][c];
    return rows;
  }
  Registry registry_;
  fs::path dir_;
};

TEST_F(ProvenanceTest, CurvesRunsSavedConfigRunsAgainWithTheSameCasesAndMetrics) {
  WritePolyline((dir_ / "my_star.obj").string(), MakeBuiltinCurve("star"));
  const Experiment exp = Load(R"(name: curves
seed: 3
datasets:
  - {name: c, kind: curves, shapes: [circle, letter_c], files: [my_star.obj]}
inputs:
  - {name: grid, pipeline: [{stage: sdf_grid_2d, params: {n: [10, 14]}}]}
methods:
  - {name: MS, pipeline: [marching_squares]}
metrics: [{stage: chamfer_2d, params: {samples: 2000}}, topology_2d]
)");
  const auto first = Run(exp, "first");
  ASSERT_EQ(first.size(), 6u);  // 3 items x 2 grids x 1 method

  // The saved file names the built-in curves as shapes and the file by its
  // absolute path (not "curve:circle" as a file).
  const fs::path saved = dir_ / "first" / "config.resolved.yaml";
  const YAML::Node doc = YAML::LoadFile(saved.string());
  ASSERT_TRUE(doc["datasets"][0]["shapes"]);
  EXPECT_EQ(doc["datasets"][0]["shapes"].size(), 2u);
  ASSERT_TRUE(doc["datasets"][0]["files"]);
  ASSERT_EQ(doc["datasets"][0]["files"].size(), 1u);
  EXPECT_EQ(doc["datasets"][0]["files"][0].as<std::string>(), fs::absolute(dir_ / "my_star.obj").lexically_normal().string());

  const Experiment again = LoadExperiment(saved.string(), {}, registry_);
  const auto a = ExpandCases(exp, registry_), b = ExpandCases(again, registry_);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].id, b[i].id) << a[i].Label();
    EXPECT_EQ(a[i].source.kind, b[i].source.kind) << a[i].Label();
  }
  const auto second = Run(again, "second");
  ASSERT_EQ(second.size(), first.size());
  for (const auto& [id, row] : first) {
    ASSERT_TRUE(second.count(id)) << id;
    for (const char* k : {"item", "chamfer_2d", "out_curve_components", "ref_components"})
      EXPECT_EQ(second.at(id).at(k), row.at(k)) << id << " " << k;
  }
}

// `method_seed: shared`: two methods with one pipeline under two names see
// the same random draws (the same points and metrics), and the saved config
// keeps the setting; by default each method has its own stream, so the same
// two give different draws (the run's results differ), as before.
TEST_F(ProvenanceTest, SharedMethodSeedGivesTwoNamesOfOnePipelineTheSameDraws) {
  const std::string body = R"(
datasets:
  - {name: c, kind: curves, shapes: [star]}
inputs:
  - {name: grid, pipeline: [{stage: sdf_grid_2d, params: {n: 16}}]}
methods:
  - {name: A, pipeline: [{stage: rfta, params: {iterations: 3}}]}
  - {name: B, pipeline: [{stage: rfta, params: {iterations: 3}}]}
metrics: [{stage: chamfer_2d, params: {samples: 2000}}]
)";
  auto by_method = [](const std::map<std::string, std::map<std::string, std::string>>& rows) {
    std::map<std::string, std::map<std::string, std::string>> m;
    for (const auto& [id, row] : rows) m[row.at("method")] = row;
    return m;
  };
  const char* cols[] = {"chamfer_2d", "free_points", "arc_points", "rfta_points"};
  const Experiment shared = Load("name: shared\nmethod_seed: shared" + body);
  EXPECT_TRUE(shared.shared_method_seed);
  const auto s = by_method(Run(shared, "shared"));
  ASSERT_EQ(s.size(), 2u);
  for (const char* k : cols) EXPECT_EQ(s.at("A").at(k), s.at("B").at(k)) << k;
  const YAML::Node saved = YAML::LoadFile((dir_ / "shared" / "config.resolved.yaml").string());
  ASSERT_TRUE(saved["method_seed"]);
  EXPECT_EQ(saved["method_seed"].as<std::string>(), "shared");

  const Experiment own = Load("name: own" + body);
  EXPECT_FALSE(own.shared_method_seed);
  const auto o = by_method(Run(own, "own"));
  ASSERT_EQ(o.size(), 2u);
  bool any_differs = false;
  for (const char* k : cols) any_differs = any_differs || o.at("A").at(k) != o.at("B").at(k);
  EXPECT_TRUE(any_differs) << "per-method streams gave two methods the same draws";
  // Case ids: shared ones differ from per-method ones (a results directory
  // never mixes the two), per-method ones are what they were.
  const auto cs = ExpandCases(shared, registry_), co = ExpandCases(own, registry_);
  ASSERT_EQ(cs.size(), co.size());
  for (size_t i = 0; i < cs.size(); ++i) EXPECT_NE(cs[i].id, co[i].id);
}

TEST_F(ProvenanceTest, MethodSeedOtherThanPerMethodOrSharedIsAnErrorNamingTheField) {
  try {
    Load("name: bad\nmethod_seed: common\nmethods:\n  - {name: MC, pipeline: [marching_cubes]}\n");
    FAIL() << "accepted method_seed: common";
  } catch (const std::exception& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("exp.yaml:2"), std::string::npos) << what;
    EXPECT_NE(what.find("method_seed"), std::string::npos) << what;
    EXPECT_NE(what.find("per_method"), std::string::npos) << what;
  }
}

TEST_F(ProvenanceTest, MeshAndPointsSavedConfigExpandsToTheSameCases) {
  WriteMesh((dir_ / "my_torus.obj").string(), MakeBuiltinShape("torus"));
  const Experiment exp = Load(R"(name: meshes
datasets:
  - {name: m, files: [my_torus.obj], shapes: [sphere, knot]}
  - {name: p, kind: points, files: [my_torus.obj], reference: my_torus.obj}
inputs:
  - {name: grid, pipeline: [{stage: sdf_grid, params: {n: [6, 8]}}]}
methods:
  - {name: MC, pipeline: [marching_cubes]}
)");
  const std::string saved = (dir_ / "resolved.yaml").string();
  {
    YAML::Emitter e;
    e << ResolvedConfig(exp, registry_);
    std::ofstream(saved) << e.c_str() << "\n";
  }
  const Experiment again = LoadExperiment(saved, {}, registry_);
  const auto a = ExpandCases(exp, registry_), b = ExpandCases(again, registry_);
  ASSERT_EQ(a.size(), 8u);  // (3 + 1) items x 2 grids
  ASSERT_EQ(b.size(), a.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].id, b[i].id) << a[i].Label();
    EXPECT_EQ(a[i].source.kind, b[i].source.kind) << a[i].Label();
    EXPECT_EQ(a[i].source.Key(), b[i].source.Key()) << a[i].Label();
  }
  EXPECT_EQ(a[0].source.kind, ItemKind::kMeshFile);
  EXPECT_EQ(a[2].source.kind, ItemKind::kBuiltinShape);
  EXPECT_EQ(a[2].source.Key(), "shape:sphere");
  EXPECT_EQ(a[6].source.kind, ItemKind::kPointFile);
}

}  // namespace
}  // namespace arcs
