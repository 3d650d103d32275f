// Components of a reconstructed surface that the SDF samples rule out (issue
// 10, "topology from the data"): every sample (p, s) is a sphere of radius
// |s| that the surface may touch but not enter (paper §3). A connected
// component of the output most of whose vertices lie inside some sphere by
// more than `tol` is a candidate: small closed bubbles that screened Poisson
// forms around stray tuning points are such components. It is removed only
// if that does not worsen the samples' fit, sum_i (|s_i| - dist(p_i, S))^2
// (the paper's E_SDF terms): a real part reconstructed slightly too fat (a
// thin feature on a coarse grid) is mostly inside spheres too, and removing
// it left its samples far from any surface (eiffel n = 20: E_SDF 0.0025 ->
// 3.44; femur n = 6: 0.0135 -> 15.4). The decision uses the samples alone,
// never a reference.
#pragma once

#include "framework/types.h"

namespace arcs {

struct ComponentFilterStats {
  int components = 0;  // before
  int dropped = 0;     // components removed
  int dropped_faces = 0;
  int kept_by_fit = 0;  // candidates kept: removing them worsened the samples' fit
};

// Removes, in place, the components of `mesh` (input frame) with more than
// `max_inside_fraction` of their vertices inside a sphere of `samples` by
// more than `tol` (input units) whose removal does not increase the samples'
// misfit. The component with the most faces is always kept. Unreferenced
// vertices are removed; the order of what is kept is preserved.
// Deterministic.
ComponentFilterStats DropInfeasibleComponents(Mesh* mesh, const SdfSamples& samples, double tol,
                                              double max_inside_fraction = 0.5);

}  // namespace arcs
