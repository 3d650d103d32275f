// Internal: structure-of-arrays face data for the dense naive (eq. 4) sums and
// their adjoints, written so that the inner loops over faces vectorise.
#pragma once

#include "framework/types.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

namespace arcs::voxel_detail {

constexpr double kInv4Pi = 0.25 / std::numbers::pi;

// Area vectors N_f = ½ (v1 - v0) × (v2 - v0) and centroids c_f of every face.
struct NaiveFaces {
  std::vector<double> nx, ny, nz, cx, cy, cz;
  double eps2 = 0.0;  // softening ε² (0 = eq. 4)
  explicit NaiveFaces(const Mesh& m, double softening = 0.0) : eps2(softening * softening) {
    const std::size_t n = m.NumFaces();
    for (auto* v : {&nx, &ny, &nz, &cx, &cy, &cz}) v->resize(n);
    for (std::size_t f = 0; f < n; ++f) {
      const Vec3 a = m.V.row(m.F(f, 0)), b = m.V.row(m.F(f, 1)), c = m.V.row(m.F(f, 2));
      const Vec3 N = 0.5 * (b - a).cross(c - a);
      const Vec3 C = (a + b + c) / 3.0;
      nx[f] = N.x(), ny[f] = N.y(), nz[f] = N.z();
      cx[f] = C.x(), cy[f] = C.y(), cz[f] = C.z();
    }
  }
  std::size_t Size() const { return nx.size(); }

  // Σ_f <N_f, c_f - q> / (4π (|c_f - q|² + ε²)^{3/2}): blocks of terms into a buffer
  // (vectorised), then summed in face order (deterministic).
  double Sum(double qx, double qy, double qz) const {
    constexpr std::size_t kBlock = 64;
    double t[kBlock];
    double sum = 0.0;
    const std::size_t n = Size();
    for (std::size_t s = 0; s < n; s += kBlock) {
      const std::size_t m = std::min(kBlock, n - s);
      const double *Nx = nx.data() + s, *Ny = ny.data() + s, *Nz = nz.data() + s;
      const double *Cx = cx.data() + s, *Cy = cy.data() + s, *Cz = cz.data() + s;
      for (std::size_t i = 0; i < m; ++i) {
        const double rx = Cx[i] - qx, ry = Cy[i] - qy, rz = Cz[i] - qz;
        const double r2 = rx * rx + ry * ry + rz * rz + eps2;
        const double d = r2 * std::sqrt(r2);
        const double inv3 = d > 0.0 ? 1.0 / d : 0.0;
        t[i] = (Nx[i] * rx + Ny[i] * ry + Nz[i] * rz) * inv3;
      }
      for (std::size_t i = 0; i < m; ++i) sum += t[i];
    }
    return sum * kInv4Pi;
  }
};

}  // namespace arcs::voxel_detail
