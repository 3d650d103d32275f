#include "registry/plugin.h"

#include "registry/plugin_api.h"

#include <dlfcn.h>

#include <algorithm>
#include <filesystem>
#include <mutex>

namespace arcs {

namespace {
std::vector<LoadedPlugin>& Loaded() {
  static std::vector<LoadedPlugin> loaded;
  return loaded;
}
std::mutex& LoadMutex() {
  static std::mutex m;
  return m;
}
}  // namespace

const std::vector<LoadedPlugin>& LoadedPlugins() { return Loaded(); }

LoadedPlugin LoadPlugin(Registry& registry, const std::string& path) {
  namespace fs = std::filesystem;
  std::lock_guard lock(LoadMutex());
  std::error_code ec;
  if (!fs::exists(path, ec)) throw Error("plugin " + path + ": file not found");
  const std::string canonical = fs::canonical(path, ec).string();
  for (const auto& p : Loaded())
    if (p.path == canonical) return p;

  void* handle = dlopen(canonical.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) throw Error("plugin " + path + ": cannot load: " + dlerror());
  using InfoFn = const ArcsPluginInfo* (*)();
  auto fn = reinterpret_cast<InfoFn>(dlsym(handle, ARCS_PLUGIN_ENTRY_SYMBOL));
  if (!fn) {
    dlclose(handle);
    throw Error("plugin " + path + ": no '" ARCS_PLUGIN_ENTRY_SYMBOL
                "' entry point (build it with the ARCS_PLUGIN macro of registry/plugin_api.h)");
  }
  const ArcsPluginInfo* info = fn();
  if (!info) {
    dlclose(handle);
    throw Error("plugin " + path + ": entry point returned no information");
  }
  if (info->api_version != ARCS_PLUGIN_API_VERSION) {
    const std::string msg = "plugin " + path + " ('" + (info->name ? info->name : "?") +
                            "') was built against arcs plugin API version " +
                            std::to_string(info->api_version) + ", but this arcs has version " +
                            std::to_string(ARCS_PLUGIN_API_VERSION) +
                            "; rebuild the plugin against this arcs";
    dlclose(handle);
    throw Error(msg);
  }
  // Register into a scratch registry first, so a failing plugin leaves the
  // host's registry untouched; then move its stages over.
  Registry scratch;
  char error[1024] = {0};
  if (info->register_stages(&scratch, error, sizeof error) != 0) {
    throw Error("plugin " + path + ": registration failed: " + error);
  }
  LoadedPlugin loaded{canonical, info->name ? info->name : "", info->version ? info->version : "", {}};
  for (const StageInfo* s : scratch.List()) {
    StageInfo copy = *s;
    copy.origin = "plugin " + canonical;
    loaded.stages.push_back(copy.name);
    registry.Register(std::move(copy));
  }
  // The handle stays open for the life of the process: the stages' code lives there.
  Loaded().push_back(loaded);
  return loaded;
}

std::vector<std::string> FindPlugins(const std::string& search_path) {
  namespace fs = std::filesystem;
  std::vector<std::string> out;
  size_t start = 0;
  while (start <= search_path.size()) {
    size_t end = search_path.find(':', start);
    if (end == std::string::npos) end = search_path.size();
    const std::string dir = search_path.substr(start, end - start);
    std::error_code ec;
    if (!dir.empty() && fs::is_directory(dir, ec)) {
      std::vector<std::string> here;
      for (const auto& e : fs::directory_iterator(dir, ec))
        if (e.path().extension() == ".so") here.push_back(e.path().string());
      std::sort(here.begin(), here.end());
      out.insert(out.end(), here.begin(), here.end());
    }
    start = end + 1;
  }
  return out;
}

}  // namespace arcs
