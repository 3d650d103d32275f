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

struct SmallComponentStats {
  int components = 0;        // before
  int candidates = 0;        // components other than the largest below the extent
  int dropped = 0;
  int dropped_faces = 0;
  double misfit_added = 0;   // what the drops added to sum_i (|s_i| - dist(p_i, S))^2 (input units^2)
};

// Removes, in place, components of `mesh` (input frame) below the samples'
// resolution that their fit does not need (issue 10, criteria 1 and 3): the
// components other than the largest (most faces) whose bounding box's
// longest side is below `max_extent` are taken smallest first, and each is
// removed while the removals together raise the samples' summed squared
// misfit sum_i (|s_i| - dist(p_i, S))^2 (the paper's E_SDF terms) by at
// most `budget` (input units^2). A sample whose nearest surface point lies
// on a removed component is then served by the nearest component left.
// Screened Poisson leaves such pieces where one or two tangency points stand
// a little off the main surface: a closed blob a few cells across, which
// the samples' fit prefers by less than a sample's misfit at half the
// spacing. Unreferenced vertices are removed; the order of what is kept is
// preserved. Deterministic.
SmallComponentStats DropSmallComponents(Mesh* mesh, const SdfSamples& samples, double max_extent, double budget);

}  // namespace arcs
