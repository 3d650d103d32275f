// The list of built-in stages: one place anyone can grep.
#pragma once

#include "registry/registry.h"

namespace arcs {

// Registers every built-in stage into `registry` (explicitly; no static
// self-registration, which static linking can silently drop).
void RegisterBuiltinStages(Registry& registry);

// The per-family registration functions, one line each in
// stages/builtin_list.h (each defined in its own translation unit).
#define ARCS_BUILTIN_STAGE(fn) void fn(Registry& r);
#include "stages/builtin_list.h"
#undef ARCS_BUILTIN_STAGE

}  // namespace arcs
