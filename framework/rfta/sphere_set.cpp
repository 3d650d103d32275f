#include "framework/rfta/sphere_set.h"

#include "framework/rfta/sphere_tree.h"
#include "framework/spatial/knn.h"
#include "framework/util/parallel.h"

#include "framework/error.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace arcs {

void CheckRftaSamples(const SdfSamples& s, const std::string& who) {
  const std::string p = who.empty() ? std::string() : who + ": ";
  if (s.dim != 2 && s.dim != 3)
    throw Error(p + "SDF samples must be 2D or 3D (dim = " + std::to_string(s.dim) + ")");
  if (s.points.rows() != s.values.size())
    throw Error(p + "SDF samples have " + std::to_string(s.points.rows()) + " points but " +
                std::to_string(s.values.size()) + " values");
  if (s.points.cols() < s.dim)
    throw Error(p + "SDF sample points have " + std::to_string(s.points.cols()) +
                " columns, need " + std::to_string(s.dim));
  if (s.Size() < 2)
    throw Error(p + "need at least 2 SDF samples (got " + std::to_string(s.Size()) + ")");
  for (std::int64_t i = 0; i < s.Size(); ++i) {
    bool ok = std::isfinite(s.values[i]);
    for (int k = 0; k < s.dim; ++k) ok = ok && std::isfinite(s.points(i, k));
    if (!ok)
      throw Error(p + "SDF sample " + std::to_string(i) + " has a non-finite point or value");
  }
  double extent = 0.0;
  for (int k = 0; k < s.dim; ++k)
    extent = std::max(extent, s.points.col(k).maxCoeff() - s.points.col(k).minCoeff());
  if (!(extent > 0.0)) throw Error(p + "all SDF sample points coincide (zero extent)");
}

Vec3 SamplePoint(const SdfSamples& s, std::int64_t i) {
  return Vec3(s.points(i, 0), s.points(i, 1), s.dim == 3 ? s.points(i, 2) : 0.0);
}

UnitFrame ComputeUnitFrame(const SdfSamples& s) {
  UnitFrame f;
  f.dim = s.dim;
  double extent = 0.0;
  for (int k = 0; k < s.dim; ++k) {
    const double lo = s.points.col(k).minCoeff(), hi = s.points.col(k).maxCoeff();
    f.translation[k] = lo;
    extent = std::max(extent, hi - lo);
  }
  f.scale = extent;
  return f;
}

void SignSplitOptions::Check() const {
  if (!(zero_radius >= 0.0 && zero_radius < 1e-2))
    throw OptionError("zero_radius = " + std::to_string(zero_radius) + ": must be in [0, 0.01)");
}

SignedSpheres SplitSpheresBySign(const SdfSamples& s, const SignSplitOptions& o) {
  o.Check();
  SignedSpheres out;
  out.frame = ComputeUnitFrame(s);
  out.num_samples = s.Size();
  std::int64_t np = 0, nn = 0;
  for (std::int64_t i = 0; i < s.Size(); ++i) {
    const double r = std::abs(s.values[i]) / out.frame.scale;
    if (r <= o.zero_radius) continue;
    (s.values[i] > 0 ? np : nn)++;
  }
  out.num_zero = s.Size() - np - nn;
  auto init = [&](SphereSet* set, std::int64_t n) {
    set->dim = s.dim;
    set->centers.resize(n, 3);
    set->radii.resize(n);
    set->sample.resize(n);
    set->wants_point.resize(n);
  };
  init(&out.positive, np);
  init(&out.negative, nn);
  std::int64_t ip = 0, in = 0;
  for (std::int64_t i = 0; i < s.Size(); ++i) {
    const double r = std::abs(s.values[i]) / out.frame.scale;
    if (r <= o.zero_radius) continue;
    SphereSet& set = s.values[i] > 0 ? out.positive : out.negative;
    std::int64_t& j = s.values[i] > 0 ? ip : in;
    set.centers.row(j) = out.frame.ToUnit(SamplePoint(s, i)).transpose();
    set.radii[j] = r;
    set.sample[j] = static_cast<int>(i);
    // Clamped SDF (paper §5.3): |s| = clamp only says "at least that far".
    // Pseudo-SDF (§5.3, Fig. 25): values of the bound sign only bound the
    // distance from below, so their spheres need not touch the surface.
    set.wants_point[j] = !(s.clamp > 0.0 && std::abs(s.values[i]) >= s.clamp) &&
                         !(s.bound_sign != 0 && (s.values[i] > 0) == (s.bound_sign > 0));
    ++j;
  }
  return out;
}

void RequireBothSigns(const SignedSpheres& sp, const std::string& who) {
  const std::string p = who.empty() ? std::string() : who + ": ";
  if (sp.positive.Size() == 0 || sp.negative.Size() == 0) {
    throw Error(p + "the SDF samples have " + std::to_string(sp.positive.Size()) +
                " positive and " + std::to_string(sp.negative.Size()) +
                " negative values (and " + std::to_string(sp.num_zero) +
                " zero): both signs are needed, otherwise there is no surface between them");
  }
}

double SamplesPerAxis(std::int64_t num_samples, int dim) {
  return std::pow(static_cast<double>(num_samples), 1.0 / dim);
}

int RasterResolutionHeuristic(std::int64_t num_samples, int dim, int cap) {
  const double n = SamplesPerAxis(num_samples, dim);
  const double r = 64.0 * std::ceil(n / 16.0);
  int res = static_cast<int>(std::min<double>(r, cap));
  if (res % 2) --res;  // "made even" (only matters for an odd cap)
  return std::max(res, 2);
}

int LocalSearchHeuristic(std::int64_t num_samples, int dim) {
  return std::max(1, static_cast<int>(std::ceil(2.0 * SamplesPerAxis(num_samples, dim))));
}

double SampleSpacing(const SdfSamples& samples) {
  if (samples.grid) {
    double h = 0;
    for (int a = 0; a < samples.grid->dim; ++a) {
      const double s = samples.grid->Spacing(a);
      if (s > 0 && (h == 0 || s < h)) h = s;
    }
    if (h > 0) return h;
  }
  const std::int64_t n = samples.points.rows();
  if (n < 2) return 0;
  MatrixX3d P = MatrixX3d::Zero(n, 3);
  P.leftCols(std::min<Eigen::Index>(3, samples.points.cols())) =
      samples.points.leftCols(std::min<Eigen::Index>(3, samples.points.cols()));
  const KdTree3 tree(P);
  Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> nn;
  tree.KnnBatch(P, 2, &nn);
  std::vector<double> d;
  d.reserve(static_cast<std::size_t>(n));
  for (std::int64_t i = 0; i < n; ++i) {
    // The nearest other sample (a point's own index can come second on duplicates).
    const int j = nn(i, 0) == i ? nn(i, 1) : nn(i, 0);
    if (j < 0) continue;
    const double dist = (P.row(i) - P.row(j)).norm();
    if (dist > 0) d.push_back(dist);
  }
  if (d.empty()) return 0;
  std::nth_element(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2), d.end());
  return d[d.size() / 2];
}

FreeSpaceSamples MergeFreeSpace(const UnitFrame& frame, const MatrixX3d& pos, const MatrixX3d& neg) {
  FreeSpaceSamples out;
  out.points.resize(pos.rows() + neg.rows(), 3);
  out.sign.resize(pos.rows() + neg.rows());
  std::int64_t j = 0;
  for (int s = 0; s < 2; ++s) {
    const MatrixX3d& P = s == 0 ? pos : neg;
    for (std::int64_t i = 0; i < P.rows(); ++i, ++j) {
      Vec3 x = frame.FromUnit(P.row(i).transpose());
      if (frame.dim == 2) x.z() = 0.0;
      out.points.row(j) = x.transpose();
      out.sign[j] = s == 0 ? 1 : -1;
    }
  }
  return out;
}

std::int64_t CountSignConflicts(const SignedSpheres& spheres, double tol, double* max_depth) {
  const SphereSet& pos = spheres.positive;
  const SphereSet& neg = spheres.negative;
  if (max_depth) *max_depth = 0.0;
  if (pos.Size() == 0 || neg.Size() == 0) return 0;
  std::vector<int> ids(neg.Size());
  for (int i = 0; i < neg.Size(); ++i) ids[i] = i;
  const SphereTree tree(neg.centers, neg.radii, ids);
  // Per-sphere results, combined in order (deterministic at any thread count).
  std::vector<double> depth(pos.Size(), 0.0);
  ParallelFor(pos.Size(), [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t i = b; i < e; ++i) {
      // Overlap of ball i with the union of negative balls: r_i - min_j (|c_i - c_j| - r_j).
      const double d = tree.DistanceToUnion(pos.centers.row(i).transpose(), 1.0);
      depth[i] = pos.radii[i] - d;
    }
  }, 256);
  std::int64_t count = 0;
  for (double d : depth) {
    if (d > tol) ++count;
    if (max_depth) *max_depth = std::max(*max_depth, d);
  }
  return count;
}

}  // namespace arcs
