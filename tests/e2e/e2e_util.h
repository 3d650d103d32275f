// Running the arcs binary from tests.
#pragma once

#include "orchestration/csv.h"
#include "tests/test_util.h"

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <sys/wait.h>

namespace arcs::testing {

struct CmdResult {
  int code = -1;
  std::string output;  // stdout and stderr
};

inline CmdResult RunCmd(const std::string& cmd) {
  CmdResult r;
  FILE* p = popen((cmd + " 2>&1").c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) r.output.append(buf.data(), n);
  const int st = pclose(p);
  r.code = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
  return r;
}

inline std::string Arcs() { return std::string("'") + ARCS_EXE + "'"; }

inline std::string ReadFile(const std::filesystem::path& p) {
  std::ifstream in(p);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// The value printed after NAME in `arcs eval`'s output ("chamfer   0.0123"); -1 when absent.
inline double Metric(const std::string& eval_output, const std::string& name) {
  std::smatch m;
  const std::regex re(name + R"(\s+([0-9.eE+-]+))");
  if (!std::regex_search(eval_output, m, re)) return -1;
  return std::stod(m[1]);
}

}  // namespace arcs::testing
