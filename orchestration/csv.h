// Minimal RFC-4180 CSV: quoted fields, '#' comment lines skipped on read.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace arcs {

struct CsvTable {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;  // each row has header.size() cells

  int Column(const std::string& name) const;  // -1 if absent
  const std::string& Cell(size_t row, const std::string& column) const;  // "" if absent
};

// Reads a CSV file; lines starting with '#' (before the header or between
// rows) are skipped. Throws InputError with the line on a malformed row.
CsvTable ReadCsv(const std::string& path);
// The same from text; `path` names it in errors.
CsvTable ParseCsv(const std::string& text, const std::string& path);

std::string CsvEscape(const std::string& field);
std::string CsvLine(const std::vector<std::string>& fields);

// A results file that rows are appended to one at a time, durably: each row
// is one write() followed by fsync(). When a row brings a column the header
// lacks, the file is rewritten (temp file + rename) with the union header.
class ResultsCsv {
 public:
  explicit ResultsCsv(std::string path);
  // Loads existing rows (if the file exists).
  const CsvTable& table() const { return table_; }
  void Append(const std::vector<std::pair<std::string, std::string>>& row);
  // Sets the initial column order (used when the file is created).
  void EnsureColumns(const std::vector<std::string>& columns);

 private:
  void Rewrite();
  std::string path_;
  CsvTable table_;
};

}  // namespace arcs
