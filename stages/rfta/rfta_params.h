// Parameter groups that several RFTA stages share (registry/bind.h).
#pragma once

#include "framework/rfta/arc_projector.h"
#include "registry/bind.h"

namespace arcs {

// Algorithm 2's settings, bound once for arc_projector and fine_tune.
inline Binder<FeasibleSearchOptions> FeasibleSearchParams() {
  using O = FeasibleSearchOptions;
  return Binder<O>()
      .Int("local_search_iters", &O::local_search_iters, "make-feasible steps per point (paper Alg. 2: 20)",
           Closed(0, 10000))
      .Int("local_searches", &O::local_searches,
           "k_search: containing spheres gathered per step; 0 = ceil(2 N^(1/d)) (paper §4.1)", Closed(0, 100000))
      .Double("tol", &O::tol, "containment/tangency tolerance in [0,1]-normalised units (official 1e-4)",
              HalfOpen(0.0, 0.1))
      .Enum("pair_choice", &O::pair_choice, kPairChoiceNames,
            "Alg. 2 candidate rule with >= 2 containing spheres: closest admissible point over all pairs (paper "
            "line 13) or first pair by radius (official code; can cycle)");
}

}  // namespace arcs
