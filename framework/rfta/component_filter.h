// Components of a reconstructed surface that the SDF samples rule out (issue
// 10, "topology from the data"): every sample (p, s) is a sphere of radius
// |s| that the surface may touch but not enter (paper §3). A connected
// component of the output most of whose vertices lie inside some sphere by
// more than `tol` cannot be part of any surface the samples describe; small
// closed bubbles that screened Poisson forms around stray tuning points are
// such components. The decision uses the samples alone, never a reference.
#pragma once

#include "framework/types.h"

namespace arcs {

struct ComponentFilterStats {
  int components = 0;  // before
  int dropped = 0;     // components removed
  int dropped_faces = 0;
};

// Removes, in place, the components of `mesh` (input frame) with more than
// `max_inside_fraction` of their vertices inside a sphere of `samples` by
// more than `tol` (input units). The component with the most faces is always
// kept. Unreferenced vertices are removed; the order of what is kept is
// preserved. Deterministic.
ComponentFilterStats DropInfeasibleComponents(Mesh* mesh, const SdfSamples& samples, double tol,
                                              double max_inside_fraction = 0.5);

}  // namespace arcs
