#include "orchestration/paths.h"

#include "framework/error.h"
#include "orchestration/version.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fnmatch.h>

namespace fs = std::filesystem;

namespace arcs {

namespace {
std::string DefaultSharedDir() { return (fs::path(SourceDir()) / ".." / "shared").lexically_normal().string(); }
}  // namespace

std::string ResolvePath(const std::string& path, const std::string& base_dir) {
  std::string out;
  for (size_t i = 0; i < path.size(); ++i) {
    if (path[i] == '$' && i + 1 < path.size() && path[i + 1] == '{') {
      const size_t end = path.find('}', i);
      if (end == std::string::npos) throw Error("unterminated ${ in path '" + path + "'");
      const std::string var = path.substr(i + 2, end - i - 2);
      const char* val = std::getenv(var.c_str());
      if (val) out += val;
      else if (var == "ARCS_SHARED_DIR") out += DefaultSharedDir();
      else if (var == "ARCS_SOURCE_DIR") out += SourceDir();
      else throw Error("environment variable ${" + var + "} used in path '" + path + "' is not set");
      i = end;
    } else {
      out += path[i];
    }
  }
  fs::path p(out);
  if (p.is_relative() && !base_dir.empty()) p = fs::path(base_dir) / p;
  return p.lexically_normal().string();
}

std::vector<std::string> Glob(const std::string& pattern) {
  const fs::path p(pattern);
  const std::string leaf = p.filename().string();
  if (leaf.find_first_of("*?[") == std::string::npos) {
    if (fs::is_regular_file(p)) return {p.string()};
    return {};
  }
  std::vector<std::string> out;
  std::error_code ec;
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  if (!fs::is_directory(dir, ec)) return {};
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    if (!e.is_regular_file()) continue;
    if (fnmatch(leaf.c_str(), e.path().filename().c_str(), 0) == 0) out.push_back(e.path().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace arcs
