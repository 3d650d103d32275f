// Structural checks of a parsed YAML document before anything decodes it:
// bounded nesting depth, no alias that refers to a node containing it (a
// cycle: every recursive walk would overflow the stack), a bounded number of
// nodes once aliases are expanded ("billion laughs"), and no duplicate key
// in a mapping (yaml-cpp keeps both; the decoder would see only one).
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>

namespace arcs {

struct YamlLimits {
  int max_depth = 64;              // nesting of maps and sequences (experiments use < 10)
  long long max_nodes = 1000000;   // nodes visited with aliases expanded
};

// Throws ExperimentError "FILE:LINE: field.path: what" (or "WHERE: field.path:
// what" when the node has no file mark, e.g. a --set value, with `where` the
// text to name instead of the file).
void CheckYamlStructure(const std::string& where, const YAML::Node& root, const YamlLimits& limits = {});

}  // namespace arcs
