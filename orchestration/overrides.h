// `--set path.to.key=value`: overrides applied to an experiment's YAML
// document before it is validated (spec.cpp), so an override is checked
// exactly like the file's own text.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>

namespace arcs {

// Applies one "--set path.to.key=value" override to a YAML document. Path
// elements index mappings by key and sequences by an element's `name` or
// `stage` (or a number); inside a stage entry, an unknown key is looked up in
// its `params`. The value is parsed as YAML ("[10, 20]" is a list). Throws
// ExperimentError naming the assignment.
void ApplyOverride(YAML::Node& doc, const std::string& assignment);

}  // namespace arcs
