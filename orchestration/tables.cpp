#include "orchestration/tables.h"

#include "framework/error.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

namespace arcs {

namespace {

bool ToNumber(const std::string& s, double* out) {
  if (s.empty()) return false;
  if (s == "inf") { *out = INFINITY; return true; }
  if (s == "-inf") { *out = -INFINITY; return true; }
  if (s == "nan") { *out = NAN; return true; }
  auto r = std::from_chars(s.data(), s.data() + s.size(), *out);
  return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

std::string Trim(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return "";
  const size_t e = s.find_last_not_of(" \t");
  return s.substr(b, e - b + 1);
}

// A results column by exact name or unique ".suffix".
int FindColumn(const CsvTable& t, const std::string& name) {
  const int exact = t.Column(name);
  if (exact >= 0) return exact;
  int found = -1;
  for (size_t i = 0; i < t.header.size(); ++i) {
    const auto& h = t.header[i];
    if (h.size() > name.size() && h.compare(h.size() - name.size() - 1, std::string::npos, "." + name) == 0) {
      if (found >= 0) throw Error("column '" + name + "' is ambiguous: '" + t.header[found] + "' and '" + h + "'");
      found = static_cast<int>(i);
    }
  }
  return found;
}

bool Compare(const std::string& a, const std::string& op, const std::string& b) {
  double x, y;
  if (ToNumber(a, &x) && ToNumber(b, &y)) {
    if (op == "==") return x == y;
    if (op == "!=") return x != y;
    if (op == "<") return x < y;
    if (op == "<=") return x <= y;
    if (op == ">") return x > y;
    if (op == ">=") return x >= y;
  } else {
    if (op == "==") return a == b;
    if (op == "!=") return a != b;
    if (op == "<") return a < b;
    if (op == "<=") return a <= b;
    if (op == ">") return a > b;
    if (op == ">=") return a >= b;
  }
  throw Error("unknown comparison '" + op + "'");
}

std::string FormatCell(double v, const std::string& fmt) {
  if (std::isnan(v)) return "–";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt.c_str(), v);
  return buf;
}

double Aggregate(std::vector<double> v, const std::string& how) {
  if (how == "count") return static_cast<double>(v.size());
  if (v.empty()) return NAN;
  if (how == "mean" || how == "std") {
    double s = 0;
    for (double x : v) s += x;
    const double mean = s / v.size();
    if (how == "mean") return mean;
    double q = 0;
    for (double x : v) q += (x - mean) * (x - mean);
    return v.size() > 1 ? std::sqrt(q / (v.size() - 1)) : 0.0;
  }
  std::sort(v.begin(), v.end());
  if (how == "min") return v.front();
  if (how == "max") return v.back();
  if (how == "median") {
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  }
  throw Error("unknown aggregate '" + how + "'");
}

// Sorts keys numerically when they all are numbers, else lexicographically
// (keeping first-appearance order for text is less surprising: methods keep YAML order).
void SortKeys(std::vector<std::string>* keys, bool keep_order_for_text) {
  bool numeric = true;
  for (const auto& k : *keys) {
    double d;
    if (!ToNumber(k, &d)) numeric = false;
  }
  if (numeric) {
    std::stable_sort(keys->begin(), keys->end(), [](const std::string& a, const std::string& b) {
      double x, y;
      ToNumber(a, &x), ToNumber(b, &y);
      return x < y;
    });
  } else if (!keep_order_for_text) {
    std::stable_sort(keys->begin(), keys->end());
  }
}

// A table or group name is part of a file name: nothing that leaves the directory.
std::string BadNameReason(const std::string& name) {
  if (name.empty()) return "is empty";
  if (name.find("..") != std::string::npos) return "contains '..'";
  if (name.find_first_of("/\\") != std::string::npos) return "contains a path separator";
  if (name.front() == '.') return "starts with '.'";
  for (unsigned char c : name)
    if (c < 0x20 || c == 0x7f) return "contains a control character";
  return "";
}

// Splits "column op value"; false when there is no operator.
bool SplitCondition(const std::string& condition, std::string* col) {
  static const char* ops[] = {"==", "!=", "<=", ">=", "<", ">"};
  for (const char* op : ops) {
    const size_t pos = condition.find(op);
    if (pos == std::string::npos) continue;
    *col = Trim(condition.substr(0, pos));
    return true;
  }
  return false;
}

// The item identity of a results row: dataset, item and input pipeline.
std::string ItemKey(const CsvTable& t, size_t r) {
  std::string k;
  for (const char* c : {"dataset", "item", "input"}) {
    const int i = t.Column(c);
    k += (i >= 0 ? t.rows[r][i] : std::string()) + "\x1f";
  }
  return k;
}

}  // namespace

bool EvalCondition(const CsvTable& t, size_t r, const std::string& condition);

namespace {

// Paired tables: keeps the ok rows `sel` of the (item, row key) pairs where
// every column key seen in the group (failed rows included) has an ok row.
std::vector<size_t> PairedRows(const CsvTable& results, const TableSpec& spec, int row_col, int col_col,
                               const std::vector<size_t>& sel, const GroupSpec& group,
                               std::map<std::string, int>* count) {
  std::set<std::string> all_cols;
  for (size_t r = 0; r < results.rows.size(); ++r) {
    bool keep = true;
    for (const auto& w : group.where) keep = keep && EvalCondition(results, r, w);
    if (keep) all_cols.insert(results.rows[r][col_col]);
  }
  std::map<std::string, std::set<std::string>> ok;  // (item, row key) -> column keys that succeeded
  for (size_t r : sel) ok[ItemKey(results, r) + results.rows[r][row_col]].insert(results.rows[r][col_col]);
  std::vector<size_t> out;
  std::set<std::string> counted;
  for (size_t r : sel) {
    const std::string key = ItemKey(results, r) + results.rows[r][row_col];
    if (ok[key].size() != all_cols.size()) continue;
    out.push_back(r);
    if (counted.insert(key).second) ++(*count)[results.rows[r][row_col]];
  }
  return out;
}

// One row per failed case: row key, item, column key, error.
BuiltTable FailuresTable(const CsvTable& results, const TableSpec& spec, int row_col, int col_col) {
  BuiltTable t;
  t.name = spec.name + "_failures";
  t.header = {spec.rows, "item", spec.columns, "error"};
  const int status = results.Column("status"), item = results.Column("item"), error = results.Column("error");
  for (size_t r = 0; r < results.rows.size(); ++r) {
    if (status < 0 || results.rows[r][status] == "ok") continue;
    t.cells.push_back({results.rows[r][row_col], item >= 0 ? results.rows[r][item] : "",
                       results.rows[r][col_col], error >= 0 ? results.rows[r][error] : ""});
  }
  t.title = spec.name + " — failed cases (" + std::to_string(t.cells.size()) + ")";
  return t;
}

}  // namespace

void ValidateTables(const std::vector<TableSpec>& specs, const std::vector<std::string>& columns,
                    const std::string& file) {
  CsvTable t;
  t.header = columns;
  for (size_t i = 0; i < specs.size(); ++i) {
    const TableSpec& spec = specs[i];
    const std::string fld = file + ": tables[" + std::to_string(i) + "]";
    auto fail = [&](const std::string& field, const std::string& msg) { throw Error(fld + field + ": " + msg); };
    if (const std::string why = BadNameReason(spec.name); !why.empty())
      fail(".name", "'" + spec.name + "' " + why + "; a table name must be a plain file name (its files go to <results>/tables/)");
    auto need = [&](const std::string& field, const std::string& name, const std::string& what) {
      int c = -1;
      try {
        c = FindColumn(t, name);
      } catch (const Error& e) {
        fail(field, e.what());
      }
      if (c < 0) {
        std::string known;
        for (const auto& h : columns)
          if (h.find('.') != std::string::npos || h.rfind("ref_", 0) == 0 || h == "method" || h == "item" ||
              h == "input" || h == "dataset")
            known += (known.empty() ? "" : ", ") + h;
        fail(field, what + " '" + name + "' is not a column of this experiment's results (known: " + known +
                        ", and the metrics' outputs)");
      }
    };
    need(".rows", spec.rows, "rows column");
    need(".columns", spec.columns, "columns column");
    // Metrics are not checked: methods write metrics of their own (timings,
    // counts) that no schema lists; one no case wrote is a warning in BuildTables.
    for (size_t g = 0; g < spec.groups.size(); ++g) {
      const std::string gf = ".groups[" + std::to_string(g) + "]";
      if (const std::string why = BadNameReason(spec.groups[g].name); !why.empty())
        fail(gf + ".name", "'" + spec.groups[g].name + "' " + why + "; a group name is part of a file name");
      for (size_t w = 0; w < spec.groups[g].where.size(); ++w) {
        const std::string& cond = spec.groups[g].where[w];
        std::string col;
        if (!SplitCondition(cond, &col))
          fail(gf + ".where", "'" + cond + "': expected 'column OP value' with OP one of == != < <= > >=");
        need(gf + ".where", col, "condition '" + cond + "': column");
      }
    }
  }
}

bool EvalCondition(const CsvTable& t, size_t r, const std::string& condition) {
  static const char* ops[] = {"==", "!=", "<=", ">=", "<", ">"};
  for (const char* op : ops) {
    const size_t pos = condition.find(op);
    if (pos == std::string::npos) continue;
    const std::string col = Trim(condition.substr(0, pos));
    const std::string val = Trim(condition.substr(pos + std::string(op).size()));
    const int c = FindColumn(t, col);
    if (c < 0) throw Error("condition '" + condition + "': no column '" + col + "' in the results");
    return Compare(t.rows[r][c], op, val);
  }
  throw Error("condition '" + condition + "': expected 'column OP value' with OP one of == != < <= > >=");
}

std::vector<BuiltTable> BuildTables(const std::vector<TableSpec>& specs, const CsvTable& results,
                                    std::vector<std::string>* warnings) {
  std::vector<BuiltTable> out;
  const int status_col = results.Column("status");
  for (const auto& spec : specs) {
    const int row_col = FindColumn(results, spec.rows);
    const int col_col = FindColumn(results, spec.columns);
    if (row_col < 0) throw Error("table '" + spec.name + "': rows column '" + spec.rows + "' not in the results");
    if (col_col < 0) throw Error("table '" + spec.name + "': columns column '" + spec.columns + "' not in the results");
    std::vector<int> metric_cols;
    for (const auto& m : spec.metrics) {
      const int c = FindColumn(results, m);
      if (c < 0 && warnings) warnings->push_back("table '" + spec.name + "': metric '" + m + "' not in the results (no successful case wrote it)");
      metric_cols.push_back(c);
    }
    // Reference CSVs.
    std::vector<CsvTable> refs(spec.references.size());
    std::vector<bool> ref_ok(spec.references.size(), false);
    for (size_t i = 0; i < spec.references.size(); ++i) {
      if (!std::filesystem::exists(spec.references[i].file)) {
        if (warnings) warnings->push_back("table '" + spec.name + "': reference file " + spec.references[i].file + " not found; reference columns left out");
        continue;
      }
      refs[i] = ReadCsv(spec.references[i].file);
      ref_ok[i] = true;
    }
    std::vector<GroupSpec> groups = spec.groups;
    if (groups.empty()) groups.push_back(GroupSpec{"all", {}});

    for (const auto& group : groups) {
      // Rows of the results in this group.
      std::vector<size_t> sel;
      for (size_t r = 0; r < results.rows.size(); ++r) {
        if (status_col >= 0 && results.rows[r][status_col] != "ok") continue;
        bool keep = true;
        for (const auto& w : group.where) keep = keep && EvalCondition(results, r, w);
        if (keep) sel.push_back(r);
      }
      std::map<std::string, int> paired_count;  // row key -> items kept (paired tables)
      if (spec.paired) sel = PairedRows(results, spec, row_col, col_col, sel, group, &paired_count);
      std::vector<std::string> row_keys, col_keys;
      for (size_t r : sel) {
        const auto& rk = results.rows[r][row_col];
        const auto& ck = results.rows[r][col_col];
        if (std::find(row_keys.begin(), row_keys.end(), rk) == row_keys.end()) row_keys.push_back(rk);
        if (std::find(col_keys.begin(), col_keys.end(), ck) == col_keys.end()) col_keys.push_back(ck);
      }
      SortKeys(&row_keys, false);
      SortKeys(&col_keys, true);
      if (!spec.column_order.empty()) {
        auto rank = [&](const std::string& k) {
          const auto it = std::find(spec.column_order.begin(), spec.column_order.end(), k);
          return it - spec.column_order.begin();  // unlisted keys rank last, in their order
        };
        std::stable_sort(col_keys.begin(), col_keys.end(),
                         [&](const std::string& a, const std::string& b) { return rank(a) < rank(b); });
      }
      // Reference rows may have keys we have no results for; include them? No:
      // rows follow our results, the reference sits beside.

      BuiltTable t;
      t.name = spec.name + (groups.size() > 1 || group.name != "all" ? "_" + group.name : "");
      t.title = spec.name + " — " + group.name + " (" + spec.aggregate + " over " + std::to_string(sel.size()) + " cases)";
      t.header.push_back(spec.rows);
      if (spec.paired) {
        t.title += ", paired: shapes where every " + spec.columns + " succeeded";
        t.header.push_back("shapes");
      }
      struct Col {
        int metric_idx;
        std::string key;       // our column key, or "" for a reference column
        size_t ref = 0;        // reference index
        std::string ref_col;
      };
      std::vector<Col> cols;
      for (size_t m = 0; m < spec.metrics.size(); ++m) {
        for (const auto& ck : col_keys) {
          t.header.push_back(spec.metrics[m] + " " + ck);
          cols.push_back({static_cast<int>(m), ck, 0, ""});
        }
        for (size_t i = 0; i < spec.references.size(); ++i) {
          if (!ref_ok[i]) continue;
          for (const auto& rc : spec.references[i].columns) {
            if (rc.metric != spec.metrics[m]) continue;
            if (refs[i].Column(rc.column) < 0) {
              if (warnings) warnings->push_back("table '" + spec.name + "': reference " + spec.references[i].file + " has no column '" + rc.column + "'");
              continue;
            }
            t.header.push_back(spec.metrics[m] + " " + rc.label);
            cols.push_back({static_cast<int>(m), "", i, rc.column});
          }
        }
      }
      for (const auto& rk : row_keys) {
        std::vector<std::string> line{rk};
        if (spec.paired) line.push_back(std::to_string(paired_count[rk]));
        for (const auto& col : cols) {
          if (!col.key.empty()) {
            const int mc = metric_cols[col.metric_idx];
            std::vector<double> vals;
            if (mc >= 0)
              for (size_t r : sel) {
                if (results.rows[r][row_col] != rk || results.rows[r][col_col] != col.key) continue;
                double v;
                if (ToNumber(results.rows[r][mc], &v)) vals.push_back(v);
              }
            line.push_back(FormatCell(Aggregate(vals, spec.aggregate), spec.aggregate == "count" ? "%.0f" : spec.format));
          } else {
            const auto& ref = refs[col.ref];
            const auto& rspec = spec.references[col.ref];
            std::string cell = "–";
            for (size_t rr = 0; rr < ref.rows.size(); ++rr) {
              bool match = true;
              for (const auto& [ref_column, ours] : rspec.match) {
                const std::string want = ours == "group" ? group.name : ours == "rows" ? rk : ours;
                const int rc = ref.Column(ref_column);
                if (rc < 0) throw Error("table '" + spec.name + "': reference " + rspec.file + " has no column '" + ref_column + "' (in match)");
                if (!Compare(ref.rows[rr][rc], "==", want)) match = false;
              }
              for (const auto& w : rspec.where) match = match && EvalCondition(ref, rr, w);
              if (match) {
                double v;
                cell = ToNumber(ref.rows[rr][ref.Column(col.ref_col)], &v) ? FormatCell(v, spec.format)
                                                                             : ref.rows[rr][ref.Column(col.ref_col)];
                break;
              }
            }
            line.push_back(cell);
          }
        }
        t.cells.push_back(std::move(line));
      }
      out.push_back(std::move(t));
    }
    if (spec.failures) out.push_back(FailuresTable(results, spec, row_col, col_col));
  }
  return out;
}

namespace {
std::string LatexEscape(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '_' || c == '%' || c == '&' || c == '#') o += '\\';
    o += c;
  }
  return o;
}

std::string Markdown(const BuiltTable& t) {
  std::string s = "### " + t.title + "\n\n|";
  for (const auto& h : t.header) s += " " + h + " |";
  s += "\n|";
  for (size_t i = 0; i < t.header.size(); ++i) s += i == 0 ? "---|" : "---:|";
  s += "\n";
  for (const auto& r : t.cells) {
    s += "|";
    for (const auto& c : r) s += " " + c + " |";
    s += "\n";
  }
  return s + "\n";
}
}  // namespace

std::string WriteTables(const std::vector<BuiltTable>& tables, const std::string& dir) {
  namespace fs = std::filesystem;
  fs::create_directories(dir);
  std::string all;
  for (const auto& t : tables) {
    if (const std::string why = BadNameReason(t.name); !why.empty())
      throw Error("table '" + t.name + "': the name " + why + "; tables are written inside " + dir + " only");
    const std::string md = Markdown(t);
    all += md;
    std::ofstream(fs::path(dir) / (t.name + ".md")) << md;
    {
      std::ofstream csv(fs::path(dir) / (t.name + ".csv"));
      csv << CsvLine(t.header);
      for (const auto& r : t.cells) csv << CsvLine(r);
    }
    {
      std::ofstream tex(fs::path(dir) / (t.name + ".tex"));
      tex << "% " << t.title << "\n\\begin{tabular}{l" << std::string(t.header.size() - 1, 'r') << "}\n\\hline\n";
      for (size_t i = 0; i < t.header.size(); ++i) tex << (i ? " & " : "") << LatexEscape(t.header[i]);
      tex << " \\\\\n\\hline\n";
      for (const auto& r : t.cells) {
        for (size_t i = 0; i < r.size(); ++i) tex << (i ? " & " : "") << LatexEscape(r[i] == "–" ? "--" : r[i]);
        tex << " \\\\\n";
      }
      tex << "\\hline\n\\end{tabular}\n";
    }
  }
  std::ofstream(fs::path(dir) / "tables.md") << all;
  return all;
}

}  // namespace arcs
