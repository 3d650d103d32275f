#include "framework/geometry/normalize.h"

#include "framework/error.h"
#include "framework/util/rng.h"

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <string>

namespace arcs {

namespace {
std::string FormatNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.17g", v);
  return buf;
}
}  // namespace

void NormalizeOptions::Check() const {
  ARCS_CHECK_OPTION(std::isfinite(longest_side) && longest_side >= 0.0, "longest_side",
                    longest_side, "a finite number >= 0 (0 = keep the scale)");
}

Similarity Similarity::Inverse() const {
  Similarity inv;
  inv.scale = 1.0 / scale;
  inv.rotation = rotation.transpose();
  inv.translation = -scale * (rotation * translation);
  return inv;
}

Similarity NormalizeTransform(const MatrixX3d& V, const NormalizeOptions& options) {
  options.Check();
  if (V.rows() == 0) throw Error("normalize: the mesh has no vertices");
  if (!V.allFinite()) throw Error("normalize: the mesh has non-finite vertex coordinates");
  const Vec3 lo = V.colwise().minCoeff().transpose();
  const Vec3 hi = V.colwise().maxCoeff().transpose();
  auto range = [&] {
    return "coordinates from (" + FormatNumber(lo[0]) + ", " + FormatNumber(lo[1]) + ", " + FormatNumber(lo[2]) +
           ") to (" + FormatNumber(hi[0]) + ", " + FormatNumber(hi[1]) + ", " + FormatNumber(hi[2]) + ")";
  };

  Similarity t;
  // The centre without overflow (lo + hi overflows near +-DBL_MAX).
  if (options.center) t.translation = -(0.5 * lo + 0.5 * hi);
  if (options.longest_side > 0.0) {
    const double side = (hi - lo).maxCoeff();
    if (side == INFINITY)
      throw Error("normalize: the bounding box's extent overflows the double range (" + range() +
                  "): the mesh cannot be scaled; rescale the file");
    if (!(side > 0.0)) throw Error("normalize: the bounding box is a single point; cannot scale");
    t.scale = options.longest_side / side;
    // A subnormal extent (all coordinates within ~1e-308) scales by more
    // than the double range, or loses every significant digit.
    if (!std::isfinite(t.scale) || side < std::numeric_limits<double>::min())
      throw Error("normalize: the bounding box's extent " + FormatNumber(side) +
                  " underflows the double range (" + range() + "): the mesh cannot be scaled; rescale the file");
  }
  // Every normalised coordinate must stay finite (a huge centre offset).
  const double reach = std::max((hi - lo).maxCoeff(), 0.0);
  if (!std::isfinite(reach * t.scale))
    throw Error("normalize: the normalised coordinates overflow (" + range() + "); rescale the file");
  if (options.random_rotation) {
    Rng rng(options.rotation_seed);
    Vec3 axis;
    for (int a = 0; a < 3; ++a) axis[a] = rng.Uniform();
    const double angle = 2.0 * std::numbers::pi * rng.Uniform();
    const double norm = axis.norm();
    if (norm > 0.0) t.rotation = Eigen::AngleAxisd(angle, axis / norm).toRotationMatrix();
  }
  return t;
}

Similarity Normalize(Mesh* mesh, const NormalizeOptions& options) {
  const Similarity t = NormalizeTransform(mesh->V, options);
  ApplySimilarity(t, &mesh->V);
  return t;
}

void ApplySimilarity(const Similarity& t, MatrixX3d* points) {
  for (Eigen::Index i = 0; i < points->rows(); ++i) {
    const Vec3 x = points->row(i).transpose();
    points->row(i) = t.Apply(x).transpose();
  }
}

Mesh ApplySimilarity(const Similarity& t, const Mesh& mesh) {
  Mesh out = mesh;
  ApplySimilarity(t, &out.V);
  return out;
}

Mesh ApplyInverseSimilarity(const Similarity& t, const Mesh& mesh) {
  return ApplySimilarity(t.Inverse(), mesh);
}

void ApplySimilarity(const Similarity& t, SdfSamples* samples) {
  if (samples->dim != 3 || samples->points.cols() != 3) {
    throw Error("ApplySimilarity: SDF samples must be 3D");
  }
  for (Eigen::Index i = 0; i < samples->points.rows(); ++i) {
    const Vec3 x = samples->points.row(i).transpose();
    samples->points.row(i) = t.Apply(x).transpose();
  }
  samples->values *= t.scale;
  samples->clamp *= t.scale;
  if (samples->grid) {
    if (!t.rotation.isIdentity(0.0)) {
      samples->grid.reset();
    } else {
      GridInfo& g = *samples->grid;
      const Vec3 a = t.Apply(Vec3(g.min[0], g.min[1], g.min[2]));
      const Vec3 b = t.Apply(Vec3(g.max[0], g.max[1], g.max[2]));
      for (int k = 0; k < 3; ++k) {
        g.min[k] = a[k];
        g.max[k] = b[k];
      }
    }
  }
}

}  // namespace arcs
