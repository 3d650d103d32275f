#include "framework/eval/metrics.h"

#include "framework/error.h"
#include "framework/geometry/surface_sampling.h"
#include "framework/spatial/knn.h"
#include "framework/spatial/triangle_bvh.h"
#include "framework/util/rng.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace arcs {
namespace {

void RequireNonEmpty(const Mesh& m, const char* metric, const char* which) {
  if (m.Empty()) throw Error(std::string(metric) + ": mesh " + which + " is empty");
}

void RequireSamples(std::int64_t samples, const char* metric) {
  if (samples < 1) {
    throw Error(std::string(metric) + ": samples = " + std::to_string(samples) + ": must be >= 1");
  }
}

// Independent sample streams for the two meshes.
std::uint64_t SeedA(std::uint64_t seed) { return HashSeed(seed, 0xA); }
std::uint64_t SeedB(std::uint64_t seed) { return HashSeed(seed, 0xB); }

double Rms(const VectorXd& sq) { return std::sqrt(sq.mean()); }

// Vertices of `m` used by at least one face, in index order.
MatrixX3d ReferencedVertices(const Mesh& m) {
  std::vector<char> used(m.V.rows(), 0);
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    for (int c = 0; c < 3; ++c) used[m.F(f, c)] = 1;
  }
  const Eigen::Index n = std::count(used.begin(), used.end(), 1);
  MatrixX3d out(n, 3);
  Eigen::Index r = 0;
  for (Eigen::Index i = 0; i < m.V.rows(); ++i) {
    if (used[i]) out.row(r++) = m.V.row(i);
  }
  return out;
}

double MaxDistance(const TriangleBvh& bvh, const MatrixX3d& Q) {
  if (Q.rows() == 0) return 0.0;
  VectorXd sq;
  bvh.ClosestPoints(Q, &sq);
  return std::sqrt(sq.maxCoeff());
}

}  // namespace

void SampledMetricOptions::Check() const {
  ARCS_CHECK_OPTION(samples >= 1 && samples <= 100000000, "samples", samples, "in [1, 1e8]");
}

double ChamferPaper(const Mesh& a, const Mesh& b, std::int64_t samples, std::uint64_t seed) {
  RequireNonEmpty(a, "ChamferPaper", "A");
  RequireNonEmpty(b, "ChamferPaper", "B");
  RequireSamples(samples, "ChamferPaper");
  const MatrixX3d pa = SampleSurfaceUniform(a, samples, SeedA(seed));
  const MatrixX3d pb = SampleSurfaceUniform(b, samples, SeedB(seed));
  VectorXd d1, d2;
  {
    const KdTree3 tb(pb);
    tb.NearestBatch(pa, nullptr, &d1);
  }
  {
    const KdTree3 ta(pa);
    ta.NearestBatch(pb, nullptr, &d2);
  }
  return Rms(d1) + Rms(d2);
}

double HausdorffPaper(const Mesh& a, const Mesh& b) {
  RequireNonEmpty(a, "HausdorffPaper", "A");
  RequireNonEmpty(b, "HausdorffPaper", "B");
  const TriangleBvh ba(a), bb(b);
  return std::max(MaxDistance(bb, ReferencedVertices(a)), MaxDistance(ba, ReferencedVertices(b)));
}

double EnergySdf(const SdfSamples& samples, const Mesh& m) {
  RequireNonEmpty(m, "EnergySdf", "M");
  if (samples.dim != 3 || samples.points.cols() != 3) {
    throw Error("EnergySdf: the SDF samples must be 3D");
  }
  if (samples.points.rows() != samples.values.size()) {
    throw Error("EnergySdf: " + std::to_string(samples.points.rows()) + " points but " +
                std::to_string(samples.values.size()) + " values");
  }
  std::vector<Eigen::Index> keep;
  keep.reserve(samples.values.size());
  for (Eigen::Index i = 0; i < samples.values.size(); ++i) {
    if (samples.clamp > 0.0 && std::abs(samples.values[i]) >= samples.clamp) continue;
    keep.push_back(i);
  }
  if (keep.empty()) return 0.0;
  MatrixX3d Q(static_cast<Eigen::Index>(keep.size()), 3);
  for (std::size_t r = 0; r < keep.size(); ++r) Q.row(r) = samples.points.row(keep[r]);
  const TriangleBvh bvh(m);
  VectorXd sq;
  bvh.ClosestPoints(Q, &sq);
  // Summed serially in index order: reproducible.
  double sum = 0.0;
  for (std::size_t r = 0; r < keep.size(); ++r) {
    const double e = std::abs(samples.values[keep[r]]) - std::sqrt(sq[r]);
    sum += e * e;
  }
  return 1000.0 * sum / static_cast<double>(keep.size());
}

double ChamferPointToSurface(const Mesh& a, const Mesh& b, std::int64_t samples,
                             std::uint64_t seed) {
  RequireNonEmpty(a, "ChamferPointToSurface", "A");
  RequireNonEmpty(b, "ChamferPointToSurface", "B");
  RequireSamples(samples, "ChamferPointToSurface");
  const MatrixX3d pa = SampleSurfaceUniform(a, samples, SeedA(seed));
  const MatrixX3d pb = SampleSurfaceUniform(b, samples, SeedB(seed));
  VectorXd d1, d2;
  TriangleBvh(b).ClosestPoints(pa, &d1);
  TriangleBvh(a).ClosestPoints(pb, &d2);
  return Rms(d1) + Rms(d2);
}

double HausdorffSampled(const Mesh& a, const Mesh& b, std::int64_t samples, std::uint64_t seed) {
  RequireNonEmpty(a, "HausdorffSampled", "A");
  RequireNonEmpty(b, "HausdorffSampled", "B");
  RequireSamples(samples, "HausdorffSampled");
  const TriangleBvh ba(a), bb(b);
  const double dv = std::max(MaxDistance(bb, ReferencedVertices(a)),
                             MaxDistance(ba, ReferencedVertices(b)));
  const double ds = std::max(MaxDistance(bb, SampleSurfaceUniform(a, samples, SeedA(seed))),
                             MaxDistance(ba, SampleSurfaceUniform(b, samples, SeedB(seed))));
  return std::max(dv, ds);
}

}  // namespace arcs
