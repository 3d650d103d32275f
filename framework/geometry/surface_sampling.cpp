#include "framework/geometry/surface_sampling.h"

#include "framework/error.h"
#include "framework/util/parallel.h"
#include "framework/util/rng.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace arcs {

MatrixX3d SampleSurfaceUniform(const Mesh& mesh, std::int64_t count, std::uint64_t seed,
                               Eigen::VectorXi* faces) {
  if (count < 0) throw Error("SampleSurfaceUniform: count = " + std::to_string(count) + " < 0");
  if (mesh.F.rows() == 0) throw Error("SampleSurfaceUniform: the mesh is empty");
  const int nf = mesh.NumFaces();
  // Cumulative (unnormalised) areas; serial so the sums are reproducible.
  std::vector<double> cdf(nf);
  double total = 0.0;
  for (int f = 0; f < nf; ++f) {
    const Vec3 a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)),
               c = mesh.V.row(mesh.F(f, 2));
    total += 0.5 * (b - a).cross(c - a).norm();
    cdf[f] = total;
  }
  if (!(total > 0.0) || !std::isfinite(total)) {
    throw Error("SampleSurfaceUniform: the mesh has zero (or non-finite) total area");
  }

  MatrixX3d P(count, 3);
  if (faces) faces->resize(count);
  ParallelFor(count, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t i = b; i < e; ++i) {
      Rng rng(HashSeed(seed, static_cast<std::uint64_t>(i)));
      const double u = rng.Uniform() * total;
      // First face whose cumulative area exceeds u (zero-area faces are never chosen).
      int f = static_cast<int>(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin());
      f = std::min(f, nf - 1);
      const double s = std::sqrt(rng.Uniform());
      const double r = rng.Uniform();
      const Vec3 a = mesh.V.row(mesh.F(f, 0)), bb = mesh.V.row(mesh.F(f, 1)),
                 c = mesh.V.row(mesh.F(f, 2));
      P.row(i) = ((1.0 - s) * a + s * (1.0 - r) * bb + s * r * c).transpose();
      if (faces) (*faces)[i] = f;
    }
  }, 4096);
  return P;
}

}  // namespace arcs
