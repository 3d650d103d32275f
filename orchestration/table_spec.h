// Table specifications (`tables:` in an experiment, or `arcs table DIR
// --tables EXP.yaml`): what BuildTables (tables.h) aggregates from results.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>
#include <utility>
#include <vector>

namespace arcs {


struct GroupSpec {
  std::string name;
  std::vector<std::string> where;  // conditions "column op value", all must hold
};

struct ReferenceColumn {
  std::string metric;  // our metric this column sits beside
  std::string column;  // column in the reference CSV
  std::string label;   // header shown in the table
};

struct ReferenceSpec {
  std::string file;                                 // resolved path ("" = none)
  std::vector<std::pair<std::string, std::string>> match;  // ref column -> "group" | "rows" | our column
  std::vector<std::string> where;                   // filters on reference rows
  std::vector<ReferenceColumn> columns;
};

struct TableSpec {
  std::string name;
  std::vector<std::string> metrics;
  std::string rows;                 // a results column (suffix match allowed)
  std::string columns = "method";   // a results column
  std::string aggregate = "mean";   // mean | median | min | max | std | count
  std::vector<GroupSpec> groups;    // default: one group "all"
  std::vector<ReferenceSpec> references;
  std::string format = "%.4g";      // printf format of cells
  // Order of the column keys (from the experiment: its methods' YAML order
  // when columns is "method"); keys not listed follow in first-appearance
  // order. Without it, text keys keep first-appearance order.
  std::vector<std::string> column_order;
  // Paired means (the RFTA paper's Table 2 convention): a (dataset, item,
  // input, row key) counts only where every column key has an ok row; adds
  // a "shapes" column with the number of such items per row.
  bool paired = false;
  // Also writes <name>_failures: one row per failed case (row key, item,
  // column key, error).
  bool failures = false;
};

// Parses a `tables:` list (paths relative to base_dir). Throws ExperimentError
// "FILE:LINE: tables[i].field: ...".
std::vector<TableSpec> ParseTables(const std::string& file, const YAML::Node& node, const std::string& base_dir);
// The tables of an experiment (or resolved config) file; other keys ignored.
std::vector<TableSpec> LoadTableSpecs(const std::string& path);
// Tables with columns "method" list the methods in the document's
// `methods:` order (not in the order cases happened to finish).
void OrderColumnsByMethods(const YAML::Node& doc, std::vector<TableSpec>* specs);

}  // namespace arcs
