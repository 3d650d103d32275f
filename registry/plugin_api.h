// The runtime plugin interface.
//
// A plugin is a shared library exporting one C function:
//
//   extern "C" const ArcsPluginInfo* arcs_plugin_info(void);
//
// The host calls it, checks `api_version` against ARCS_PLUGIN_API_VERSION
// before anything else, then calls `register_stages` with its own Registry
// (so a plugin never registers into a copy). No exception crosses the C
// boundary: register_stages returns 0 on success, or non-zero with a message
// in `error`. Use the ARCS_PLUGIN macro below instead of writing this by hand:
//
//   static void Register(arcs::Registry& r) { r.Register({...}); }
//   ARCS_PLUGIN("my_plugin", "1.0", Register)
//
// Plugins are built against these headers with the same compiler and
// standard library as the host; the framework's symbols come from the host
// executable (which exports them), so a plugin links no arcs library itself.
#pragma once

#include "registry/registry.h"

#include <cstddef>
#include <cstdio>
#include <exception>
#include <cstdint>

// Bump on any change to Registry, StageInfo, Stage, CaseData, ParamMap or
// the framework types that a plugin may touch.
//   1: the first.
//   2: the stage contract: Stage::Run is not virtual (a Stage subclass
//      overrides Execute); StageInfo declares reads/writes/dims/check;
//      CaseData::stage_seconds; the parameter binder (registry/bind.h).
#ifndef ARCS_PLUGIN_API_VERSION
#define ARCS_PLUGIN_API_VERSION 2
#endif

extern "C" {
struct ArcsPluginInfo {
  std::uint32_t api_version;
  const char* name;
  const char* version;
  // `registry` is an arcs::Registry*. Returns 0 on success.
  int (*register_stages)(void* registry, char* error, std::size_t error_size);
};
}

#define ARCS_PLUGIN_ENTRY_SYMBOL "arcs_plugin_info"

#define ARCS_PLUGIN(NAME, VERSION, REGISTER_FN)                                         \
  namespace {                                                                           \
  int ArcsPluginRegisterTrampoline(void* registry, char* error, std::size_t size) {     \
    try {                                                                               \
      REGISTER_FN(*static_cast<::arcs::Registry*>(registry));                           \
      return 0;                                                                         \
    } catch (const std::exception& e) {                                                 \
      std::snprintf(error, size, "%s", e.what());                                       \
    } catch (...) {                                                                     \
      std::snprintf(error, size, "unknown exception");                                  \
    }                                                                                   \
    return 1;                                                                           \
  }                                                                                     \
  }                                                                                     \
  extern "C" __attribute__((visibility("default"))) const ArcsPluginInfo*               \
  arcs_plugin_info(void) {                                                              \
    static const ArcsPluginInfo info{ARCS_PLUGIN_API_VERSION, NAME, VERSION,            \
                                     &ArcsPluginRegisterTrampoline};                    \
    return &info;                                                                       \
  }
