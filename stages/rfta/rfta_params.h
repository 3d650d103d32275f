// Parameter groups that several RFTA stages share (registry/bind.h).
#pragma once

#include "framework/rfta/arc_projector.h"
#include "framework/rfta/fine_tune.h"
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

// fine_tune's final check against all spheres, declared once for the
// fine_tune stage and the rfta stage (which forwards it): the names, the
// default (FineTuneOptions::kDefaultFinalCheck) and the doc.
inline Binder<FineTuneOptions>& FinalCheckParam(Binder<FineTuneOptions>& b) {
  return b.Enum("final_check", &FineTuneOptions::final_check, FineTuneOptions::kFinalCheckNames,
                "after the last iteration, tuned points inside any sphere (all of them, not a batch) by more than "
                "tol: dropped (drop), repaired by Alg. 2 against all spheres and dropped when that fails (repair), "
                "or kept (off, the paper's algorithm). The metrics final_infeasible_before / final_repaired / "
                "final_dropped / final_infeasible (violators left) are recorded in every mode");
}

// The final check's counts as case metrics, in every mode (written by the
// fine_tune stage and by rfta's fine-tuning part).
inline void SetFinalCheckMetrics(CaseData& d, const FineTuneResult& res) {
  d.SetMetric("final_infeasible_before", static_cast<double>(res.final_infeasible_before));
  d.SetMetric("final_repaired", static_cast<double>(res.final_repaired));
  d.SetMetric("final_dropped", static_cast<double>(res.final_dropped));
  d.SetMetric("final_infeasible", static_cast<double>(res.final_infeasible));
  d.SetMetric("final_check_s", res.final_check_s);
}

}  // namespace arcs
