// Analytic SDF samples for the RFTA tests: a ball and a disc, exact distances.
#pragma once

#include "framework/types.h"

#include <cmath>

namespace arcs::rfta_test {

// The (n+1)^d nodes of linspace(lo, hi, n+1)^d (x fastest) with the exact
// SDF of the ball / disc of radius R centred at `center` (negative inside).
inline SdfSamples BallSdfGrid(int n, double R, int dim = 3, double lo = -0.5, double hi = 0.5,
                              const Vec3& center = Vec3::Zero()) {
  SdfSamples s;
  s.dim = dim;
  const int m = n + 1;
  const int nz = dim == 3 ? m : 1;
  s.points.resize(static_cast<std::int64_t>(m) * m * nz, dim);
  s.values.resize(s.points.rows());
  std::int64_t t = 0;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i, ++t) {
        const Vec3 p(lo + (hi - lo) * i / n, lo + (hi - lo) * j / n, dim == 3 ? lo + (hi - lo) * k / n : 0.0);
        for (int a = 0; a < dim; ++a) s.points(t, a) = p[a];
        s.values[t] = (p - center).norm() - R;
      }
  GridInfo g;
  g.dim = dim;
  g.dims = {m, m, nz};
  g.min = {lo, lo, dim == 3 ? lo : 0.0};
  g.max = {hi, hi, dim == 3 ? hi : 0.0};
  s.grid = g;
  return s;
}

}  // namespace arcs::rfta_test
