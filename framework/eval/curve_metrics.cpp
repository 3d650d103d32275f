#include "framework/eval/curve_metrics.h"

#include "framework/error.h"
#include "framework/geometry/curves.h"
#include "framework/spatial/knn.h"
#include "framework/spatial/polyline_query.h"
#include "framework/util/parallel.h"
#include "framework/util/rng.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace arcs {

namespace {

void RequireCurve(const Polyline& c, const char* what) {
  if (c.Empty()) throw Error(std::string(what) + ": the curve is empty (no edges)");
  CheckPolyline(c, what);
  if (!(PolylineLength(c) > 0)) throw Error(std::string(what) + ": the curve has zero length");
}

// Vertices referenced by an edge.
MatrixX3d UsedVertices(const Polyline& c) {
  std::vector<char> used(c.NumVertices(), 0);
  for (int e = 0; e < c.NumEdges(); ++e) used[c.E(e, 0)] = used[c.E(e, 1)] = 1;
  MatrixX3d V(std::count(used.begin(), used.end(), 1), 3);
  int k = 0;
  for (int v = 0; v < c.NumVertices(); ++v)
    if (used[v]) V.row(k++) = c.V.row(v);
  return V;
}

double MaxDistTo(const SegmentBvh& bvh, const MatrixX3d& Q) {
  if (Q.rows() == 0) return 0.0;
  VectorXd sq;
  bvh.ClosestPoints(Q, &sq);
  return std::sqrt(sq.maxCoeff());
}

}  // namespace

MatrixX3d SampleCurve(const Polyline& curve, std::int64_t count, std::uint64_t seed) {
  if (count < 0) throw OptionError("SampleCurve: count = " + std::to_string(count) + ": must be >= 0");
  RequireCurve(curve, "SampleCurve");
  const int ne = curve.NumEdges();
  std::vector<double> cum(ne + 1, 0.0);
  for (int e = 0; e < ne; ++e)
    cum[e + 1] = cum[e] + (curve.V.row(curve.E(e, 1)) - curve.V.row(curve.E(e, 0))).norm();
  const double total = cum[ne];
  MatrixX3d S(count, 3);
  ParallelFor(count, [&](std::int64_t b, std::int64_t end) {
    for (std::int64_t i = b; i < end; ++i) {
      Rng rng(HashSeed(seed, static_cast<std::uint64_t>(i)));
      const double s = rng.Uniform() * total;
      int e = static_cast<int>(std::upper_bound(cum.begin(), cum.end(), s) - cum.begin()) - 1;
      e = std::clamp(e, 0, ne - 1);
      while (e < ne - 1 && cum[e + 1] - cum[e] <= 0) ++e;  // skip zero-length edges
      const double len = cum[e + 1] - cum[e];
      const double t = len > 0 ? std::clamp((s - cum[e]) / len, 0.0, 1.0) : 0.0;
      S.row(i) = (1 - t) * curve.V.row(curve.E(e, 0)) + t * curve.V.row(curve.E(e, 1));
      S(i, 2) = 0.0;
    }
  }, 4096);
  return S;
}

double ChamferCurves(const Polyline& a, const Polyline& b, std::int64_t samples, std::uint64_t seed) {
  if (samples < 1) throw OptionError("chamfer_2d: samples = " + std::to_string(samples) + ": must be >= 1");
  RequireCurve(a, "chamfer_2d (output)");
  RequireCurve(b, "chamfer_2d (reference)");
  const MatrixX3d sa = SampleCurve(a, samples, HashSeed(seed, 1));
  const MatrixX3d sb = SampleCurve(b, samples, HashSeed(seed, 2));
  auto rms = [](const KdTree3& tree, const MatrixX3d& Q) {
    Eigen::VectorXi idx;
    VectorXd sq;
    tree.NearestBatch(Q, &idx, &sq);
    return std::sqrt(sq.mean());
  };
  return rms(KdTree3(sb), sa) + rms(KdTree3(sa), sb);
}

double HausdorffCurves(const Polyline& a, const Polyline& b, std::int64_t samples, std::uint64_t seed) {
  if (samples < 0) throw OptionError("hausdorff_2d: samples = " + std::to_string(samples) + ": must be >= 0");
  RequireCurve(a, "hausdorff_2d (output)");
  RequireCurve(b, "hausdorff_2d (reference)");
  const SegmentBvh ba(a), bb(b);
  double h = std::max(MaxDistTo(bb, UsedVertices(a)), MaxDistTo(ba, UsedVertices(b)));
  if (samples > 0) {
    h = std::max(h, MaxDistTo(bb, SampleCurve(a, samples, HashSeed(seed, 1))));
    h = std::max(h, MaxDistTo(ba, SampleCurve(b, samples, HashSeed(seed, 2))));
  }
  return h;
}

double EnergySdf2D(const SdfSamples& samples, const Polyline& curve) {
  if (samples.dim != 2) throw Error("e_sdf_2d: the samples are " + std::to_string(samples.dim) + "D, expected 2D");
  RequireCurve(curve, "e_sdf_2d (output)");
  const SegmentBvh bvh(curve);
  MatrixX3d Q = MatrixX3d::Zero(samples.points.rows(), 3);
  Q.leftCols<2>() = samples.points.leftCols(2);
  VectorXd sq;
  bvh.ClosestPoints(Q, &sq);
  double sum = 0;
  std::int64_t n = 0;
  for (Eigen::Index i = 0; i < Q.rows(); ++i) {
    const double s = std::abs(samples.values[i]);
    if (samples.clamp > 0 && s >= samples.clamp) continue;
    const double d = s - std::sqrt(sq[i]);
    sum += d * d;
    ++n;
  }
  return n > 0 ? 1000.0 * sum / n : 0.0;
}

}  // namespace arcs
