// The list of built-in stages: one place anyone can grep.
#pragma once

#include "registry/registry.h"

namespace arcs {

// Registers every built-in stage into `registry` (explicitly; no static
// self-registration, which static linking can silently drop).
void RegisterBuiltinStages(Registry& registry);

// Per-family registration functions (each in its own translation unit).
void RegisterSdfGrid(Registry& r);
void RegisterSdfRandom(Registry& r);
void RegisterSdfFile(Registry& r);
void RegisterSdfNoise(Registry& r);
void RegisterSdfClamp(Registry& r);
void RegisterMarchingCubes(Registry& r);
void RegisterEvalStages(Registry& r);

}  // namespace arcs
