#include "framework/points/sample_points.h"

#include "framework/error.h"
#include "framework/geometry/surface_sampling.h"
#include "framework/util/rng.h"

#include <Eigen/Geometry>

#include <cmath>

namespace arcs {

void SurfacePointOptions::Check() const {
  ARCS_CHECK_OPTION(count >= 1 && count <= 100000000, "count", count, "in [1, 1e8]");
  ARCS_CHECK_OPTION(noise_sigma >= 0 && noise_sigma <= 1, "noise_sigma", noise_sigma, "in [0, 1]");
  ARCS_CHECK_OPTION(outlier_fraction >= 0 && outlier_fraction <= 1, "outlier_fraction", outlier_fraction, "in [0, 1]");
  ARCS_CHECK_OPTION(duplicate_fraction >= 0 && duplicate_fraction <= 1, "duplicate_fraction", duplicate_fraction,
                    "in [0, 1]");
}

PointCloud SampleSurfacePoints(const Mesh& mesh, const SurfacePointOptions& o, std::uint64_t seed) {
  o.Check();
  Eigen::VectorXi faces;
  const MatrixX3d S = SampleSurfaceUniform(mesh, o.count, HashSeed(seed, 1), &faces);
  const std::int64_t n = o.count;
  const std::int64_t n_out = static_cast<std::int64_t>(std::llround(o.outlier_fraction * n));
  const std::int64_t n_dup = static_cast<std::int64_t>(std::llround(o.duplicate_fraction * n));
  PointCloud pc;
  pc.P.resize(n + n_out + n_dup, 3);
  pc.N.resize(n + n_out + n_dup, 3);
  pc.P.topRows(n) = S;
  for (std::int64_t i = 0; i < n; ++i) {
    const int f = faces[i];
    const Vec3 a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)), c = mesh.V.row(mesh.F(f, 2));
    pc.N.row(i) = (b - a).cross(c - a).normalized().transpose();  // zero-area faces are never drawn
  }
  if (o.noise_sigma > 0) {
    Rng rng(HashSeed(seed, 2));
    for (std::int64_t i = 0; i < n; ++i)
      for (int k = 0; k < 3; ++k) pc.P(i, k) += o.noise_sigma * rng.Normal();
  }
  if (n_out > 0) {
    Rng rng(HashSeed(seed, 3));
    const Vec3 lo = mesh.V.colwise().minCoeff().transpose(), hi = mesh.V.colwise().maxCoeff().transpose();
    const Vec3 pad = 0.1 * (hi - lo);
    for (std::int64_t i = n; i < n + n_out; ++i) {
      for (int k = 0; k < 3; ++k) pc.P(i, k) = rng.Uniform(lo[k] - pad[k], hi[k] + pad[k]);
      Vec3 d;
      do {
        d = Vec3(rng.Normal(), rng.Normal(), rng.Normal());
      } while (d.norm() < 1e-9);
      pc.N.row(i) = d.normalized().transpose();
    }
  }
  if (n_dup > 0) {
    Rng rng(HashSeed(seed, 4));
    for (std::int64_t i = n + n_out; i < n + n_out + n_dup; ++i) {
      const auto j = static_cast<std::int64_t>(rng.UniformInt(static_cast<std::uint64_t>(n)));
      pc.P.row(i) = pc.P.row(j);
      pc.N.row(i) = pc.N.row(j);
    }
  }
  return pc;
}

}  // namespace arcs
