#include "orchestration/csv.h"
#include "orchestration/spec.h"
#include "orchestration/tables.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

namespace arcs {
namespace {

CsvTable Results() {
  CsvTable t;
  t.header = {"case_id", "status", "item", "method", "sdf_grid.n", "ref_genus", "chamfer"};
  t.rows = {
      {"1", "ok", "a", "MC", "10", "0", "1.0"},   {"2", "ok", "b", "MC", "10", "3", "3.0"},
      {"3", "ok", "c", "MC", "10", "12", "8.0"},  {"4", "failed", "d", "MC", "10", "0", ""},
      {"5", "ok", "a", "MC", "20", "0", "0.5"},   {"6", "ok", "b", "MC", "20", "3", "1.5"},
      {"7", "ok", "a", "RFTA", "10", "0", "0.2"}, {"8", "ok", "b", "RFTA", "20", "3", "0.1"},
  };
  return t;
}

TEST(TablesTest, GroupsAggregateAndSortRowsNumerically) {
  TableSpec spec;
  spec.name = "t";
  spec.metrics = {"chamfer"};
  spec.rows = "n";  // suffix of sdf_grid.n
  spec.groups = {{"all", {}}, {"genus_gt0", {"ref_genus > 0"}}, {"genus_gt10", {"ref_genus > 10"}}};
  spec.format = "%.3f";
  std::vector<std::string> warnings;
  const auto tables = BuildTables({spec}, Results(), &warnings);
  ASSERT_EQ(tables.size(), 3u);
  // all: n=10 MC mean of 1,3,8 (the failed row is ignored) = 4; RFTA 0.2.
  EXPECT_EQ(tables[0].header, (std::vector<std::string>{"n", "chamfer MC", "chamfer RFTA"}));
  ASSERT_EQ(tables[0].cells.size(), 2u);
  EXPECT_EQ(tables[0].cells[0], (std::vector<std::string>{"10", "4.000", "0.200"}));
  EXPECT_EQ(tables[0].cells[1], (std::vector<std::string>{"20", "1.000", "0.100"}));
  // genus > 0: n=10 MC mean of 3, 8.
  EXPECT_EQ(tables[1].cells[0][1], "5.500");
  EXPECT_EQ(tables[1].cells[0][2], "–") << "no RFTA row with genus > 0 at n=10";
  // genus > 10: only item c.
  EXPECT_EQ(tables[2].cells[0][1], "8.000");

  spec.aggregate = "median";
  spec.groups = {};
  EXPECT_EQ(BuildTables({spec}, Results(), &warnings)[0].cells[0][1], "3.000");
  spec.aggregate = "count";
  EXPECT_EQ(BuildTables({spec}, Results(), &warnings)[0].cells[0][1], "3");
}

// Cases finish in any order with --jobs > 1: the method columns follow the
// experiment's order of methods, not the rows' order.
TEST(TablesTest, MethodColumnsFollowTheExperimentOrder) {
  CsvTable r = Results();
  std::rotate(r.rows.begin(), r.rows.begin() + 6, r.rows.end());  // RFTA rows first
  TableSpec spec;
  spec.name = "t";
  spec.metrics = {"chamfer"};
  spec.rows = "n";
  EXPECT_EQ(BuildTables({spec}, r, nullptr)[0].header,
            (std::vector<std::string>{"n", "chamfer RFTA", "chamfer MC"}))
      << "without an order, first appearance";
  spec.column_order = {"MC", "RFTA"};
  EXPECT_EQ(BuildTables({spec}, r, nullptr)[0].header, (std::vector<std::string>{"n", "chamfer MC", "chamfer RFTA"}));
  // Read from an experiment file's methods.
  const auto dir = testing::TempDir("tables_order");
  std::ofstream(dir / "e.yaml") << "methods:\n  - name: MC\n    pipeline: [marching_cubes]\n"
                                   "  - name: RFTA\n    pipeline: [rfta]\n"
                                   "tables:\n  - name: t\n    metrics: [chamfer]\n    rows: n\n";
  const auto specs = LoadTableSpecs((dir / "e.yaml").string());
  ASSERT_EQ(specs.size(), 1u);
  EXPECT_EQ(specs[0].column_order, (std::vector<std::string>{"MC", "RFTA"}));
  EXPECT_EQ(BuildTables(specs, r, nullptr)[0].header, (std::vector<std::string>{"n", "chamfer MC", "chamfer RFTA"}));
}

TEST(TablesTest, ReferenceColumnsSitBesideOurs) {
  const auto dir = testing::TempDir("tables_ref");
  std::ofstream(dir / "ref.csv") << "# a comment line\ngroup,grid,chamfer_mc\nall,10,0.17\nall,20,0.07\ngenus0,10,0.15\n";
  TableSpec spec;
  spec.name = "t";
  spec.metrics = {"chamfer"};
  spec.rows = "sdf_grid.n";
  ReferenceSpec ref;
  ref.file = (dir / "ref.csv").string();
  ref.match = {{"group", "group"}, {"grid", "rows"}};
  ref.columns = {{"chamfer", "chamfer_mc", "MC (paper)"}};
  spec.references = {ref};
  std::vector<std::string> warnings;
  const auto t = BuildTables({spec}, Results(), &warnings);
  ASSERT_EQ(t.size(), 1u);
  EXPECT_EQ(t[0].header.back(), "chamfer MC (paper)");
  EXPECT_EQ(t[0].cells[0].back(), "0.17");
  EXPECT_EQ(t[0].cells[1].back(), "0.07");
  // A missing reference file is a warning, not an error.
  spec.references[0].file = (dir / "missing.csv").string();
  warnings.clear();
  const auto t2 = BuildTables({spec}, Results(), &warnings);
  EXPECT_EQ(t2[0].header.size(), 3u);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("missing.csv"), std::string::npos);
  // Outputs: Markdown, CSV and LaTeX.
  const std::string md = WriteTables(t, (dir / "out").string());
  EXPECT_NE(md.find("| 10 | 4 | 0.2 | 0.17 |"), std::string::npos) << md;
  EXPECT_TRUE(std::filesystem::exists(dir / "out" / "t.tex"));
  const CsvTable back = ReadCsv((dir / "out" / "t.csv").string());
  EXPECT_EQ(back.rows.size(), 2u);
}

TEST(TablesTest, ConditionsAreCheckedAndUnknownColumnsReported) {
  const CsvTable t = Results();
  EXPECT_TRUE(EvalCondition(t, 2, "ref_genus > 10"));
  EXPECT_FALSE(EvalCondition(t, 0, "ref_genus != 0"));
  EXPECT_TRUE(EvalCondition(t, 0, "method == MC"));
  EXPECT_THROW(EvalCondition(t, 0, "no_such_column == 1"), Error);
  EXPECT_THROW(EvalCondition(t, 0, "ref_genus ~ 1"), Error);
}

TEST(CsvTest, QuotingRoundTripsAndTruncatedLastLineIsDropped) {
  const auto dir = testing::TempDir("csv_rt");
  const std::string path = (dir / "r.csv").string();
  {
    ResultsCsv csv(path);
    csv.EnsureColumns({"a", "b"});
    csv.Append({{"a", "x,y"}, {"b", "say \"hi\"\nthere"}});
    csv.Append({{"a", "2"}, {"c", "new column"}});  // a new column rewrites the header
  }
  CsvTable t = ReadCsv(path);
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_EQ(t.Cell(0, "a"), "x,y");
  EXPECT_EQ(t.Cell(0, "b"), "say \"hi\"\nthere");
  EXPECT_EQ(t.Cell(1, "c"), "new column");
  // An interrupted write leaves a partial last line: it is ignored on resume.
  std::ofstream(path, std::ios::app) << "3,partial";
  EXPECT_EQ(ReadCsv(path).rows.size(), 2u);
}

}  // namespace
}  // namespace arcs
