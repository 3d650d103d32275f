// Paired tables (means over the items where every method succeeded, with a
// shapes column) and the failures table (one row per failed case and error).
#include "orchestration/csv.h"
#include "orchestration/spec.h"
#include "orchestration/tables.h"

#include <gtest/gtest.h>

namespace arcs {
namespace {

CsvTable Results() {
  CsvTable t;
  t.header = {"case_id", "status", "error", "dataset", "item", "input", "method", "sdf_grid.n", "ref_genus", "chamfer"};
  t.rows = {
      {"1", "ok", "", "d", "a", "g", "MC", "10", "0", "1.0"},
      {"2", "ok", "", "d", "b", "g", "MC", "10", "3", "3.0"},
      {"3", "ok", "", "d", "c", "g", "MC", "10", "0", "8.0"},
      {"4", "ok", "", "d", "a", "g", "RFTS", "10", "0", "0.5"},
      {"5", "failed", "rfts: genus", "d", "b", "g", "RFTS", "10", "3", ""},
      {"6", "ok", "", "d", "c", "g", "RFTS", "10", "0", "2.0"},
      {"7", "ok", "", "d", "a", "g", "MC", "20", "0", "0.4"},
      {"8", "ok", "", "d", "a", "g", "RFTS", "20", "0", "0.2"},
  };
  return t;
}

TableSpec Spec() {
  TableSpec spec;
  spec.name = "t";
  spec.metrics = {"chamfer"};
  spec.rows = "n";
  spec.format = "%.2f";
  return spec;
}

TEST(TablesPairedTest, UnpairedMeansUseEveryOkRow) {
  const auto t = BuildTables({Spec()}, Results(), nullptr);
  ASSERT_EQ(t.size(), 1u);
  EXPECT_EQ(t[0].cells[0], (std::vector<std::string>{"10", "4.00", "1.25"}));  // MC over a, b, c; RFTS over a, c
}

TEST(TablesPairedTest, PairedMeansSkipItemsWhereAnyMethodFailed) {
  TableSpec spec = Spec();
  spec.paired = true;
  const auto t = BuildTables({spec}, Results(), nullptr);
  ASSERT_EQ(t.size(), 1u);
  EXPECT_EQ(t[0].header, (std::vector<std::string>{"n", "shapes", "chamfer MC", "chamfer RFTS"}));
  ASSERT_EQ(t[0].cells.size(), 2u);
  EXPECT_EQ(t[0].cells[0], (std::vector<std::string>{"10", "2", "4.50", "1.25"}));  // b left out: RFTS failed
  EXPECT_EQ(t[0].cells[1], (std::vector<std::string>{"20", "1", "0.40", "0.20"}));
  // Per group: genus > 0 has only b, which RFTS failed: no row.
  spec.groups = {{"genus_gt0", {"ref_genus > 0"}}};
  const auto g = BuildTables({spec}, Results(), nullptr);
  EXPECT_TRUE(g[0].cells.empty());
}

TEST(TablesPairedTest, FailuresTableListsEachFailedCaseWithItsError) {
  TableSpec spec = Spec();
  spec.failures = true;
  const auto t = BuildTables({spec}, Results(), nullptr);
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[1].name, "t_failures");
  EXPECT_EQ(t[1].header, (std::vector<std::string>{"n", "item", "method", "error"}));
  ASSERT_EQ(t[1].cells.size(), 1u);
  EXPECT_EQ(t[1].cells[0], (std::vector<std::string>{"10", "b", "RFTS", "rfts: genus"}));
}

}  // namespace
}  // namespace arcs
