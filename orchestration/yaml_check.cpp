#include "orchestration/yaml_check.h"

#include "orchestration/yaml_decode.h"

#include <map>
#include <vector>

namespace arcs {
namespace {

struct Walker {
  const std::string& where;
  const YamlLimits& limits;
  std::vector<YAML::Node> path;  // ancestors of the node being visited
  long long visited = 0;

  std::string Loc(const YAML::Node& n) const {
    if (n.IsDefined() && n.Mark().line >= 0) return where + ":" + std::to_string(n.Mark().line + 1);
    return where;
  }
  [[noreturn]] void Fail(const YAML::Node& n, const std::string& field, const std::string& what) const {
    throw ExperimentError(Loc(n) + ": " + (field.empty() ? std::string("(top level)") : field) + ": " + what);
  }

  void Visit(const YAML::Node& n, const std::string& field) {
    if (++visited > limits.max_nodes)
      Fail(n, field, "more than " + std::to_string(limits.max_nodes) +
                         " YAML nodes once aliases are expanded (an alias bomb?)");
    if (!n.IsMap() && !n.IsSequence()) return;
    for (const YAML::Node& a : path)
      if (a.is(n)) Fail(n, field, "a YAML alias refers to a node that contains it (a cycle)");
    if (static_cast<int>(path.size()) >= limits.max_depth)
      Fail(n, field, "nested deeper than " + std::to_string(limits.max_depth) + " levels");
    path.push_back(n);
    if (n.IsSequence()) {
      for (std::size_t i = 0; i < n.size(); ++i) Visit(n[i], field + "[" + std::to_string(i) + "]");
    } else {
      std::map<std::string, int> seen;  // scalar key -> line (1-based, 0 = unknown)
      for (const auto& kv : n) {
        const YAML::Node& k = kv.first;
        std::string key = k.IsScalar() ? k.Scalar() : std::string("<complex key>");
        const std::string sub = field.empty() ? key : field + "." + key;
        if (k.IsMap() || k.IsSequence()) Fail(k, sub, "a mapping key must be a plain value");
        const int line = k.Mark().line >= 0 ? k.Mark().line + 1 : 0;
        const auto [it, fresh] = seen.emplace(key, line);
        if (!fresh)
          Fail(k, sub, "duplicate key '" + key + "'" +
                           (it->second > 0 ? " (first at line " + std::to_string(it->second) + ")" : ""));
        Visit(kv.second, sub);
      }
    }
    path.pop_back();
  }
};

}  // namespace

void CheckYamlStructure(const std::string& where, const YAML::Node& root, const YamlLimits& limits) {
  Walker w{where, limits, {}, 0};
  w.Visit(root, "");
}

}  // namespace arcs
