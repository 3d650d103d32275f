// Hostile experiment files and --set values: a deterministic mutation fuzzer
// over a small experiment YAML (a clear error or success, never a signal, a
// sanitizer finding or a timeout), and the structural errors of
// CheckYamlStructure with FILE:LINE: field.
#include "orchestration/expand.h"
#include "orchestration/spec.h"
#include "stages/builtin.h"
#include "tests/fuzz_util.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>

namespace arcs {
namespace {

const char* kSeedYaml = R"(name: fuzz
seed: 3
case_timeout_s: 0
datasets:
  - name: shapes
    shapes: [sphere, torus]
    normalize: {longest_side: 1.0, center: true}
inputs:
  - name: grid
    pipeline:
      - stage: sdf_grid
        params: {n: [6, 10], inside: voxelizer}
      - stage: sdf_noise
        params: {sigma: 0.001}
methods:
  - name: MC
    pipeline: [marching_cubes]
  - &m
    name: MC2
    pipeline:
      - stage: marching_cubes
        params: {level: [0.0, 0.01]}
metrics: [chamfer, hausdorff]
tables:
  - name: t2
    metrics: [chamfer]
    rows: n
    columns: method
    aggregate: mean
    groups: [{name: all}, {name: g0, where: "ref_genus == 0"}]
)";

int Mutants() {
  if (const char* e = std::getenv("ARCS_FUZZ_MUTANTS")) return std::max(1, std::atoi(e));
  return 300;
}

void LoadAndExpand(const std::string& path, const std::vector<std::string>& sets = {}) {
  Registry registry;
  RegisterBuiltinStages(registry);
  const Experiment exp = LoadExperiment(path, sets, registry);
  ExpandCases(exp, registry);
}

TEST(ExperimentFuzz, MutatedExperimentsFailCleanly) {
  testing::FuzzReader("yaml", kSeedYaml, ".yaml", Mutants(), 201, [](const std::string& p) { LoadAndExpand(p); });
}

// Hostile --set values on the good file: each a clear error (or a valid
// override), never a crash or a hang.
TEST(ExperimentFuzz, HostileSetValuesFailCleanly) {
  const auto dir = testing::TempDir("experiment_fuzz_set");
  const std::string path = (dir / "e.yaml").string();
  std::ofstream(path) << kSeedYaml;
  std::string deep = "x=";
  for (int i = 0; i < 5000; ++i) deep += "[";
  const std::vector<std::string> sets = {
      "seed=&a [*a]",                     // a self-referential alias
      "inputs.grid.sdf_grid.n=&a {k: *a}",
      "seed=&a [&b [*a, *b]]",
      deep,                               // nesting beyond yaml-cpp's own limit
      "methods.MCC.marching_cubes.level=0.1",    // no such method
      "methods.MC.marching_cubez.level=0.1",     // no such stage in it
      "methods.7.marching_cubes.level=0.1",      // no such index
      "inputs.grid.sdf_grid.n=4294967302",
      "inputs.grid.sdf_grid.n=-1",
      "inputs.grid.sdf_grid.n=[]",
      "seed=99999999999999999999999",
      "seed=",
      "=3",
      "datasets.shapes.shapes=[nosuchshape]",
      "tables.t2.rows=nosuchcolumn",
      "case_timeout_s=nan",
  };
  for (const auto& s : sets) {
    const std::string why = testing::RunIsolated([&] { LoadAndExpand(path, {s}); }, 10);
    EXPECT_EQ(why, "") << "--set " << s.substr(0, 60);
  }
}

class YamlStructure : public ::testing::Test {
 protected:
  void SetUp() override { RegisterBuiltinStages(registry_); }
  std::string Error(const std::string& yaml, const std::vector<std::string>& sets = {}) {
    const auto dir = testing::TempDir(std::string("yaml_structure_") +
                                      ::testing::UnitTest::GetInstance()->current_test_info()->name());
    const std::string path = (dir / "x.yaml").string();
    std::ofstream(path) << yaml;
    try {
      LoadExperiment(path, sets, registry_);
    } catch (const ExperimentError& e) {
      return e.what();
    }
    return "";
  }
  Registry registry_;
};

TEST_F(YamlStructure, DuplicateKeysAreRefusedWithBothLines) {
  const std::string e = Error("name: a\nseed: 1\ndatasets:\n  - name: d\n    shapes: [sphere]\n    shapes: [torus]\n");
  EXPECT_NE(e.find("x.yaml:6: datasets[0].shapes: duplicate key 'shapes' (first at line 5)"), std::string::npos) << e;
  const std::string top = Error("name: a\nseed: 1\nseed: 2\n");
  EXPECT_NE(top.find("x.yaml:3: seed: duplicate key 'seed' (first at line 2)"), std::string::npos) << top;
}

TEST_F(YamlStructure, SelfReferentialAliasesAreRefused) {
  const std::string e = Error("name: a\nseed: &s [1, *s]\n");
  EXPECT_NE(e.find("x.yaml:2: seed"), std::string::npos) << e;
  EXPECT_NE(e.find("cycle"), std::string::npos) << e;
  const std::string s = Error(std::string(kSeedYaml), {"seed=&a [*a]"});
  EXPECT_NE(s.find("--set seed"), std::string::npos) << s;
  EXPECT_NE(s.find("cycle"), std::string::npos) << s;
}

TEST_F(YamlStructure, AliasBombsAndDeepNestingAreRefused) {
  std::string bomb = "name: a\nl0: &l0 [1, 1, 1, 1, 1, 1, 1, 1, 1, 1]\n";
  for (int i = 1; i <= 8; ++i)
    bomb += "l" + std::to_string(i) + ": &l" + std::to_string(i) + " [" + [&] {
      std::string r;
      for (int k = 0; k < 10; ++k) {
        r += k ? ", *l" : "*l";
        r += std::to_string(i - 1);
      }
      return r;
    }() + "]\n";
  EXPECT_NE(Error(bomb).find("aliases are expanded"), std::string::npos);
  std::string deep = "name: a\nseed: ";
  for (int i = 0; i < 100; ++i) deep += "[";
  for (int i = 0; i < 100; ++i) deep += "]";
  EXPECT_NE(Error(deep + "\n").find("nested deeper than 64"), std::string::npos);
}

TEST_F(YamlStructure, SetIntoAMissingListElementIsAnError) {
  const std::string e = Error(kSeedYaml, {"methods.MCC.marching_cubes.level=0.1"});
  EXPECT_NE(e.find("MCC"), std::string::npos) << e;
  const std::string s = Error(kSeedYaml, {"inputs.grid.sdf_grdi.n=3"});
  EXPECT_NE(s.find("sdf_grdi"), std::string::npos) << s;
}

}  // namespace
}  // namespace arcs
