#include "orchestration/csv.h"

#include "framework/error.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace arcs {

int CsvTable::Column(const std::string& name) const {
  for (size_t i = 0; i < header.size(); ++i)
    if (header[i] == name) return static_cast<int>(i);
  return -1;
}

const std::string& CsvTable::Cell(size_t row, const std::string& column) const {
  static const std::string empty;
  const int c = Column(column);
  if (c < 0 || row >= rows.size() || static_cast<size_t>(c) >= rows[row].size()) return empty;
  return rows[row][c];
}

std::string CsvEscape(const std::string& field) {
  if (field.find_first_of(",\"\n\r") == std::string::npos) return field;
  std::string out = "\"";
  for (char c : field) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

std::string CsvLine(const std::vector<std::string>& fields) {
  std::string line;
  for (size_t i = 0; i < fields.size(); ++i) line += (i ? "," : "") + CsvEscape(fields[i]);
  return line + "\n";
}

CsvTable ReadCsv(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "cannot open CSV file");
  std::stringstream ss;
  ss << in.rdbuf();
  return ParseCsv(ss.str(), path);
}

CsvTable ParseCsv(const std::string& text, const std::string& path) {
  CsvTable t;
  size_t i = 0;
  long line = 1;
  bool have_header = false;
  while (i < text.size()) {
    // Skip comment lines and blank lines.
    if (text[i] == '#' || text[i] == '\n' || text[i] == '\r') {
      while (i < text.size() && text[i] != '\n') ++i;
      ++i, ++line;
      continue;
    }
    const long row_line = line;
    std::vector<std::string> fields;
    std::string cur;
    bool quoted = false, done = false;
    while (!done) {
      if (i >= text.size()) {
        if (quoted) throw InputError(path, row_line, "unterminated quoted field");
        fields.push_back(cur);
        break;
      }
      const char c = text[i++];
      if (quoted) {
        if (c == '"') {
          if (i < text.size() && text[i] == '"') cur += '"', ++i;
          else quoted = false;
        } else {
          if (c == '\n') ++line;
          cur += c;
        }
      } else if (c == '"') {
        quoted = true;
      } else if (c == ',') {
        fields.push_back(std::move(cur));
        cur.clear();
      } else if (c == '\n') {
        fields.push_back(std::move(cur));
        ++line;
        done = true;
      } else if (c != '\r') {
        cur += c;
      }
    }
    if (!have_header) {
      t.header = std::move(fields);
      have_header = true;
    } else {
      if (fields.size() != t.header.size()) {
        // A truncated last line (interrupted write) is dropped, anything else is an error.
        if (i >= text.size() && text.back() != '\n') break;
        throw InputError(path, row_line, "row has " + std::to_string(fields.size()) + " fields, header has " +
                                             std::to_string(t.header.size()));
      }
      t.rows.push_back(std::move(fields));
    }
  }
  return t;
}

ResultsCsv::ResultsCsv(std::string path) : path_(std::move(path)) {
  if (std::filesystem::exists(path_)) table_ = ReadCsv(path_);
}

void ResultsCsv::EnsureColumns(const std::vector<std::string>& columns) {
  bool changed = false;
  for (const auto& c : columns) {
    if (table_.Column(c) < 0) {
      table_.header.push_back(c);
      for (auto& r : table_.rows) r.emplace_back();
      changed = true;
    }
  }
  if (changed || !std::filesystem::exists(path_)) Rewrite();
}

void ResultsCsv::Rewrite() {
  const std::string tmp = path_ + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw Error("cannot write " + tmp);
    out << CsvLine(table_.header);
    for (const auto& r : table_.rows) out << CsvLine(r);
    out.flush();
    if (!out) throw Error("cannot write " + tmp);
  }
  std::filesystem::rename(tmp, path_);
}

void ResultsCsv::Append(const std::vector<std::pair<std::string, std::string>>& row) {
  std::vector<std::string> missing;
  for (const auto& [k, v] : row)
    if (table_.Column(k) < 0) missing.push_back(k);
  if (!missing.empty()) EnsureColumns(missing);
  std::vector<std::string> cells(table_.header.size());
  for (const auto& [k, v] : row) cells[table_.Column(k)] = v;
  table_.rows.push_back(cells);
  const std::string line = CsvLine(cells);
  const int fd = ::open(path_.c_str(), O_WRONLY | O_APPEND | O_CREAT, 0644);
  if (fd < 0) throw Error("cannot append to " + path_);
  const off_t before = ::lseek(fd, 0, SEEK_END);
  const ssize_t w = ::write(fd, line.data(), line.size());
  // A partial row (disk full) is taken back, so the file stays whole.
  if (w != static_cast<ssize_t>(line.size()) && before >= 0) (void)::ftruncate(fd, before);
  ::fsync(fd);
  ::close(fd);
  if (w != static_cast<ssize_t>(line.size())) throw Error("short write to " + path_ + " (disk full?); the row was not kept");
}

}  // namespace arcs
