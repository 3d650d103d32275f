// Metrics between 2D curves: the paper's Chamfer and Hausdorff (framework/
// eval/metrics.h) on polylines. Every function throws Error when a curve has
// no edges or zero length (a metric on an empty output fails the case, as in
// 3D), and OptionError on a sample count < 0.
#pragma once

#include "framework/types.h"

#include <cstdint>

namespace arcs {

// `count` points uniform by length on the curve's edges (z = 0); point i is
// drawn from HashSeed(seed, i) (independent of the thread count).
MatrixX3d SampleCurve(const Polyline& curve, std::int64_t count, std::uint64_t seed);

// The paper's Chamfer on curves: `samples` length-uniform points on each
// curve, d1 = distance of each sample of A to the nearest *sample* of B
// (kd-tree), d2 likewise; sqrt(mean d1^2) + sqrt(mean d2^2). The two sample
// sets use independent seeds from `seed`, so ChamferCurves(A, A) is the
// sampling floor (about 2e-5 for a unit circle at 10^5 samples), not 0.
double ChamferCurves(const Polyline& a, const Polyline& b, std::int64_t samples = 100000, std::uint64_t seed = 1);

// Two-sided Hausdorff: the max over the vertices (and, when samples > 0,
// `samples` length-uniform points) of each curve of the exact distance to the
// other curve's segments. samples = 0 is the paper's vertex-only lower bound.
double HausdorffCurves(const Polyline& a, const Polyline& b, std::int64_t samples = 100000, std::uint64_t seed = 1);

// 1000 * mean_i (|s_i| - dist(p_i, curve))^2 over the 2D SDF samples (the
// paper's E_SDF); clamped samples (|s| >= clamp > 0) are left out.
double EnergySdf2D(const SdfSamples& samples, const Polyline& curve);

}  // namespace arcs
