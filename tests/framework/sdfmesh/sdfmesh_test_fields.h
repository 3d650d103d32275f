// Analytic SDF fields on regular grids for the SDF -> mesh baseline tests.
#pragma once

#include "framework/types.h"

#include <algorithm>
#include <cmath>
#include <functional>

namespace arcs::testing {

// Samples f at the nodes of linspace(lo, hi, n + 1)^3 (GridInfo order).
inline SdfSamples GridSamples(int n, double lo, double hi, const std::function<double(const Vec3&)>& f) {
  SdfSamples s;
  s.dim = 3;
  GridInfo g;
  g.dim = 3;
  g.dims = {n + 1, n + 1, n + 1};
  g.min = {lo, lo, lo};
  g.max = {hi, hi, hi};
  const std::int64_t N = g.NumNodes();
  s.points.resize(N, 3);
  s.values.resize(N);
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        const std::int64_t id = i + (n + 1) * (j + std::int64_t{n + 1} * k);
        const Vec3 p(lo + (hi - lo) * i / n, lo + (hi - lo) * j / n, lo + (hi - lo) * k / n);
        s.points.row(id) = p.transpose();
        s.values[id] = f(p);
      }
  s.grid = g;
  return s;
}

inline double SphereSdf(const Vec3& p, double r, const Vec3& c = Vec3::Zero()) { return (p - c).norm() - r; }

// Exact SDF of the axis-aligned box with half extents b about c.
inline double BoxSdf(const Vec3& p, const Vec3& b, const Vec3& c = Vec3::Zero()) {
  const Vec3 q = (p - c).cwiseAbs() - b;
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

// Exact SDF of a torus about the z axis (major radius R, minor r).
inline double TorusSdf(const Vec3& p, double R, double r) {
  const double qx = std::hypot(p.x(), p.y()) - R;
  return std::hypot(qx, p.z()) - r;
}

}  // namespace arcs::testing
