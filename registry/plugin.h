// Loading runtime plugins into a registry.
#pragma once

#include "registry/registry.h"

#include <string>
#include <vector>

namespace arcs {

struct LoadedPlugin {
  std::string path;
  std::string name;
  std::string version;
  std::vector<std::string> stages;  // names it registered
};

// dlopens `path`, checks the API version and registers its stages (their
// origin is "plugin <path>"). Throws Error with a clear message on a missing
// file, a missing entry point, a version mismatch or a registration failure.
// Loading the same file twice is a no-op returning the first result.
LoadedPlugin LoadPlugin(Registry& registry, const std::string& path);

// Plugin files found in the directories of a ':'-separated search path
// (e.g. $ARCS_PLUGIN_PATH): every *.so file in each directory, sorted.
std::vector<std::string> FindPlugins(const std::string& search_path);

// The plugins loaded so far in this process.
const std::vector<LoadedPlugin>& LoadedPlugins();

}  // namespace arcs
