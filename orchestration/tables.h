// Tables from results rows: grouped, aggregated, with reference columns from
// the papers' CSVs beside ours; written as Markdown, CSV and LaTeX.
#pragma once

#include "orchestration/csv.h"
#include "orchestration/table_spec.h"

#include <string>
#include <vector>

namespace arcs {

struct BuiltTable {
  std::string name;     // table name, with the group: "table2_chamfer" ...
  std::string title;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> cells;
};

// Evaluates "column op value" (op: == != < <= > >=; numeric when both sides
// parse as numbers) on row `r` of `t`. Throws Error for a malformed condition
// or an unknown column.
bool EvalCondition(const CsvTable& t, size_t r, const std::string& condition);

// Builds every table of `specs` from `results` (only rows with status ok).
// Missing reference files produce a warning in `warnings` and no column.
std::vector<BuiltTable> BuildTables(const std::vector<TableSpec>& specs, const CsvTable& results,
                                    std::vector<std::string>* warnings);

// Checks table specs against the columns the results will have, before any
// case runs: `rows`, `columns` and every group's `where` must name a column (a unique suffix is enough), and table and group names must be
// plain file names (no '/', no '..': the files stay inside the results
// directory). Throws Error "FILE: tables[i].field: ..." naming the mistake.
void ValidateTables(const std::vector<TableSpec>& specs, const std::vector<std::string>& columns,
                    const std::string& file);

// Writes <dir>/<name>.md, .csv, .tex for each table, and <dir>/tables.md
// with all of them. Returns the Markdown of all tables.
std::string WriteTables(const std::vector<BuiltTable>& tables, const std::string& dir);

}  // namespace arcs
