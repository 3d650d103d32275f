#include "framework/sdf/sdf2d.h"

#include "framework/error.h"
#include "framework/geometry/curves.h"
#include "framework/spatial/polyline_query.h"
#include "framework/util/parallel.h"

#include <cmath>
#include <vector>

namespace arcs {

void SdfGrid2DOptions::Check() const {
  ARCS_CHECK_OPTION(n >= 1 && n <= kMaxN, "sdf_grid_2d.n", n, "in [1, " + std::to_string(kMaxN) + "]");
  if (!(std::isfinite(lo) && std::isfinite(hi) && hi > lo))
    throw OptionError("sdf_grid_2d: the box [lo, hi] must be finite with hi > lo (lo = " + std::to_string(lo) +
                      ", hi = " + std::to_string(hi) + ")");
}

VectorXd SignedDistance2D(const Polyline& curve, const MatrixXd& points) {
  CheckPolyline(curve, "SignedDistance2D: curve");
  if (points.cols() < 2) throw Error("SignedDistance2D: points need 2 or 3 columns");
  MatrixX3d Q(points.rows(), 3);
  Q.leftCols<2>() = points.leftCols(2);
  Q.col(2).setZero();
  const SegmentBvh bvh(curve);
  VectorXd sq;
  bvh.ClosestPoints(Q, &sq);
  const VectorXd w = WindingNumbers2D(curve, Q);
  VectorXd s(Q.rows());
  for (Eigen::Index i = 0; i < Q.rows(); ++i) s[i] = (w[i] > 0.5 ? -1.0 : 1.0) * std::sqrt(sq[i]);
  return s;
}

SdfSamples SampleSdfGrid2D(const Polyline& curve, const SdfGrid2DOptions& options, const Context& ctx) {
  options.Check();
  CheckPolyline(curve, "sdf_grid_2d: reference curve");
  const int m = options.n + 1;
  GridInfo grid;
  grid.dim = 2;
  grid.dims = {m, m, 1};
  grid.min = {options.lo, options.lo, 0.0};
  grid.max = {options.hi, options.hi, 0.0};
  // linspace(lo, hi, n+1), last node exactly hi (as SampleSdfGrid).
  std::vector<double> c(m);
  const double h = (options.hi - options.lo) / options.n;
  for (int i = 0; i < m; ++i) c[i] = options.lo + i * h;
  c.back() = options.hi;
  SdfSamples out;
  out.dim = 2;
  out.points.resize(static_cast<Eigen::Index>(m) * m, 2);
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i) {
      out.points(i + static_cast<Eigen::Index>(m) * j, 0) = c[i];
      out.points(i + static_cast<Eigen::Index>(m) * j, 1) = c[j];
    }
  ctx.CheckStop();
  out.values = SignedDistance2D(curve, out.points);
  out.grid = grid;
  return out;
}

SdfSamples SampleSdfRandom2D(const Polyline& curve, std::int64_t count, double lo, double hi, const Context& ctx) {
  if (count < 1) throw OptionError("sdf_random_2d: count = " + std::to_string(count) + ": must be >= 1");
  if (!(std::isfinite(lo) && std::isfinite(hi) && hi > lo))
    throw OptionError("sdf_random_2d: the box [lo, hi] must be finite with hi > lo");
  CheckPolyline(curve, "sdf_random_2d: reference curve");
  const std::uint64_t seed = ctx.StreamSeed("sdf_random_2d");
  SdfSamples out;
  out.dim = 2;
  out.points.resize(count, 2);
  ParallelFor(count, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t i = b; i < e; ++i) {
      Rng rng(HashSeed(seed, static_cast<std::uint64_t>(i)));
      out.points(i, 0) = rng.Uniform(lo, hi);
      out.points(i, 1) = rng.Uniform(lo, hi);
    }
  }, 4096);
  ctx.CheckStop();
  out.values = SignedDistance2D(curve, out.points);
  return out;
}

}  // namespace arcs
