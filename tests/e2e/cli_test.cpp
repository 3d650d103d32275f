// End-to-end tests of the `arcs` program on built-in shapes (no shared data).
#include "tests/e2e/e2e_util.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <map>

namespace arcs {
namespace {

using testing::Arcs;
using testing::RunCmd;

const char* kSmall = R"(name: small
seed: 5
datasets:
  - name: shapes
    shapes: [sphere, torus]
inputs:
  - name: grid
    pipeline:
      - stage: sdf_grid
        params: {n: [8, 12]}
methods:
  - name: MC
    pipeline: [marching_cubes]
metrics:
  - {stage: chamfer, params: {samples: 20000}}
  - hausdorff
  - e_sdf
  - topology
  - mesh_size
tables:
  - name: chamfer_by_n
    metrics: [chamfer, hausdorff]
    rows: n
    columns: method
)";

TEST(CliTest, ListAndDescribeShowStagesAndDefaults) {
  const auto list = RunCmd(Arcs() + " list");
  ASSERT_EQ(list.code, 0) << list.output;
  for (const char* s : {"sdf_grid", "sdf_random", "sdf_noise", "sdf_clamp", "marching_cubes", "chamfer", "hausdorff",
                        "e_sdf", "chamfer_p2s", "hausdorff_sampled", "topology", "mesh_size"})
    EXPECT_NE(list.output.find(s), std::string::npos) << s;
  const auto d = RunCmd(Arcs() + " describe sdf_grid");
  ASSERT_EQ(d.code, 0) << d.output;
  EXPECT_NE(d.output.find("[1, 2048]"), std::string::npos) << d.output;
  EXPECT_NE(d.output.find("fast_winding_number"), std::string::npos) << d.output;
  const auto bad = RunCmd(Arcs() + " describe sdf_gird");
  EXPECT_NE(bad.code, 0);
  EXPECT_NE(bad.output.find("did you mean 'sdf_grid'"), std::string::npos) << bad.output;
}

std::map<std::string, std::map<std::string, std::string>> RowsById(const std::string& csv_path) {
  const CsvTable t = ReadCsv(csv_path);
  std::map<std::string, std::map<std::string, std::string>> out;
  for (size_t r = 0; r < t.rows.size(); ++r)
    for (size_t c = 0; c < t.header.size(); ++c) out[t.Cell(r, "case_id")][t.header[c]] = t.rows[r][c];
  return out;
}

TEST(CliTest, RunIsDeterministicAcrossJobsAndResumes) {
  const auto dir = testing::TempDir("cli_run");
  testing::WriteFile(dir / "small.yaml", kSmall);
  const auto r1 = RunCmd(Arcs() + " run " + (dir / "small.yaml").string() + " --jobs 1 --out " + (dir / "j1").string());
  ASSERT_EQ(r1.code, 0) << r1.output;
  const auto r2 = RunCmd(Arcs() + " run " + (dir / "small.yaml").string() + " --jobs 2 --out " + (dir / "j2").string());
  ASSERT_EQ(r2.code, 0) << r2.output;

  const auto a = RowsById((dir / "j1" / "results.csv").string());
  const auto b = RowsById((dir / "j2" / "results.csv").string());
  ASSERT_EQ(a.size(), 4u);
  ASSERT_EQ(b.size(), 4u);
  for (const auto& [id, row] : a) {
    ASSERT_TRUE(b.count(id)) << id;
    EXPECT_EQ(row.at("status"), "ok") << row.at("error");
    for (const char* m : {"chamfer", "hausdorff", "e_sdf", "out_genus", "out_faces"})
      EXPECT_EQ(row.at(m), b.at(id).at(m)) << m << " differs between --jobs 1 and 2";
    EXPECT_EQ(row.at("out_closed"), "1");
    // Genus of the output: sphere 0, torus 1 (the grids resolve both).
    EXPECT_EQ(row.at("out_genus"), row.at("item") == "torus" ? "1" : "0") << row.at("item");
    EXPECT_EQ(row.at("ref_genus"), row.at("item") == "torus" ? "1" : "0");
    // Finer grid, smaller error.
  }
  // Provenance and resolved config are saved.
  const std::string prov = testing::ReadFile(dir / "j1" / "provenance.yaml");
  for (const char* k : {"git_revision", "build_type", "host", "seed: 5", "plugins"})
    EXPECT_NE(prov.find(k), std::string::npos) << k << " missing from provenance";
  EXPECT_NE(testing::ReadFile(dir / "j1" / "config.resolved.yaml").find("level"), std::string::npos)
      << "defaults are filled into the resolved config";
  EXPECT_TRUE(std::filesystem::exists(dir / "j1" / "tables" / "chamfer_by_n.md"));
  EXPECT_TRUE(std::filesystem::exists(dir / "j1" / "tables" / "chamfer_by_n.tex"));

  // Re-running resumes: everything is skipped, nothing is appended.
  const auto r3 = RunCmd(Arcs() + " run " + (dir / "small.yaml").string() + " --out " + (dir / "j1").string());
  ASSERT_EQ(r3.code, 0) << r3.output;
  EXPECT_NE(r3.output.find("4 skipped"), std::string::npos) << r3.output;
  EXPECT_EQ(ReadCsv((dir / "j1" / "results.csv").string()).rows.size(), 4u);

  // `arcs table` rebuilds the tables from the CSV alone.
  std::filesystem::remove_all(dir / "j1" / "tables");
  const auto t = RunCmd(Arcs() + " table " + (dir / "j1").string());
  ASSERT_EQ(t.code, 0) << t.output;
  EXPECT_TRUE(std::filesystem::exists(dir / "j1" / "tables" / "chamfer_by_n.csv"));
  EXPECT_NE(t.output.find("| 12 |"), std::string::npos) << t.output;
}

TEST(CliTest, MalformedYamlIsOneLineWithFileAndLine) {
  const auto dir = testing::TempDir("cli_bad_yaml");
  testing::WriteFile(dir / "bad.yaml", "name: x\ndatasets:\n  - shapes: [sphere]\n    normalize: {random_rotaton: true}\n"
                                       "methods: [{pipeline: [marching_cubes]}]\n");
  const auto r = RunCmd(Arcs() + " run " + (dir / "bad.yaml").string() + " --out " + (dir / "out").string());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.output.find("bad.yaml:4"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("did you mean 'random_rotation'"), std::string::npos) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "results.csv")) << "validation happens before any work";
}

}  // namespace
}  // namespace arcs
