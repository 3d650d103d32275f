// The registry with every built-in stage, made once per test program (for
// tests that link the stages).
#pragma once

#include "registry/registry.h"
#include "stages/builtin.h"

namespace arcs::testing {

inline const Registry& Builtins() {
  static const Registry r = [] {
    Registry x;
    RegisterBuiltinStages(x);
    return x;
  }();
  return r;
}

}  // namespace arcs::testing
