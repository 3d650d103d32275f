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
// units; see CarveMargin), the negated distance to the balls' union
// elsewhere (1-Lipschitz). `near` computes c for a batch of points in
// parallel, each block of points against the balls that can reach it;
// `value` by a tree query. 3D samples only (throws Error otherwise, and when
// no sample is positive). Thread-safe and deterministic.
CarveField OutsideSpheresCarve(const SdfSamples& samples, double margin);

// The margin (input units): max(tol_unit x the samples' unit-frame scale,
// fraction x SampleSpacing(samples)).
double CarveMargin(const SdfSamples& samples, double tol_unit, double fraction);

}  // namespace arcs
