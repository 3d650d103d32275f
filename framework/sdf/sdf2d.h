// Signed distances to a 2D polyline, and the paper's sampling protocol in the
// plane: exact distance to the segments, sign from the 2D winding number
// (w > 1/2 -> negative, inside), grid nodes of linspace(lo, hi, n+1)^2.
#pragma once

#include "framework/context.h"
#include "framework/types.h"

#include <cstdint>

namespace arcs {

// Signed distances of the rows of `points` (N x 2 or N x 3, z ignored) to
// `curve`: |s| = distance to the nearest segment, s < 0 iff the winding
// number w > 1/2. Throws InputError when the curve is unusable (no edges,
// non-finite, z != 0, bad indices).
VectorXd SignedDistance2D(const Polyline& curve, const MatrixXd& points);

struct SdfGrid2DOptions {
  static constexpr int kMaxN = 1 << 14;  // the largest n (the stage's and the CLI's bound too)
  int n = 20;        // cells per axis: (n+1)^2 nodes of linspace(lo, hi, n+1)^2 (paper protocol)
  double lo = -1.0;  // box lower corner on both axes (paper: -1; the shape fills about [-0.5, 0.5]^2)
  double hi = 1.0;   // box upper corner (paper: 1)
  void Check() const;
};

// The (n+1)^2 grid nodes with their signed distances, dim = 2, in GridInfo
// order (index = i + (n+1) j, x fastest; grid->dim = 2, dims[2] = 1).
SdfSamples SampleSdfGrid2D(const Polyline& curve, const SdfGrid2DOptions& options, const Context& ctx);

// `count` points uniform in [lo, hi]^2 (point i from HashSeed(ctx.StreamSeed(
// "sdf_random_2d"), i): independent of the thread count), dim = 2.
SdfSamples SampleSdfRandom2D(const Polyline& curve, std::int64_t count, double lo, double hi, const Context& ctx);

}  // namespace arcs
