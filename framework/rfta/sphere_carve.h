// The carving field of the outside spheres (issue 10, "topology from the
// data"): every sample with s > 0 certifies that the open ball of radius s
// around it holds no surface and lies outside the shape. A surface
// reconstructed from RFTA's tangency points can still cut through such balls
// where no point pins it down: sheets across a hollow, bulges over a concave
// part. Carving the balls out of the reconstruction's solid removes exactly
// what the samples rule out and nothing else; the screened Poisson's
// marching cubes takes the field (SpsrOptions::carve).
#pragma once

#include "framework/reconstruct/spsr.h"
#include "framework/types.h"

namespace arcs {

using CarveField = SpsrCarve;

// c(x) = max over the samples with s > 0 of (s - |x - p|) - margin: positive
// where x lies inside an outside sample's ball by more than `margin` (input
// units; RFTA passes its tol, 1e-4 of the samples' largest extent), the
// negated distance to the balls' union elsewhere. `claims` answers c > 0 by
// a containment query (a ball with |x - p| < s - margin; in parallel),
// `value` computes c. 3D samples only (throws Error otherwise, and when no
// sample is positive). Thread-safe and deterministic.
CarveField OutsideSpheresCarve(const SdfSamples& samples, double margin);

// The margin (input units): max(tol_unit x the samples' unit-frame scale,
// fraction x SampleSpacing(samples)).
double CarveMargin(const SdfSamples& samples, double tol_unit, double fraction);

}  // namespace arcs
