#include "framework/reconstruct/poisson2d.h"

#include "framework/error.h"
#include "framework/geometry/curves.h"
#include "framework/geometry/marching_cubes.h"
#include "framework/spatial/knn.h"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <vector>

namespace arcs {

void Poisson2DOptions::Check() const {
  ARCS_CHECK_OPTION(resolution == 0 || (resolution >= 4 && resolution <= 4096), "screened_poisson_2d.resolution",
                    resolution, "0 (automatic) or in [4, 4096]");
  ARCS_CHECK_OPTION(resolution_shift >= -4 && resolution_shift <= 4, "screened_poisson_2d.resolution_shift",
                    resolution_shift, "in [-4, 4]");
  ARCS_CHECK_OPTION(std::isfinite(screening) && screening >= 0 && screening <= 1e6, "screened_poisson_2d.screening",
                    screening, "in [0, 1e6]");
  ARCS_CHECK_OPTION(std::isfinite(scale) && scale > 1.0 && scale <= 16, "screened_poisson_2d.scale", scale,
                    "in (1, 16]");
  ARCS_CHECK_OPTION(neighbours >= 1 && neighbours <= 64, "screened_poisson_2d.neighbours", neighbours, "in [1, 64]");
  ARCS_CHECK_OPTION(std::isfinite(smoothing) && smoothing >= 0 && smoothing <= 16, "screened_poisson_2d.smoothing",
                    smoothing, "in [0, 16]");
}

int Poisson2DResolution(const Poisson2DOptions& options, int num_points) {
  if (options.resolution > 0) return options.resolution;
  const double want = 4.0 * std::sqrt(std::max(num_points, 1));
  int p = 6;  // 64
  while ((1 << p) < want && p < 10) ++p;
  p = std::clamp(p + options.resolution_shift, 2, 12);
  return 1 << p;
}

Polyline ReconstructPoisson2D(const PointCloud& pc, const Poisson2DOptions& options, const Context& ctx,
                              Poisson2DInfo* info) {
  options.Check();
  const int n = pc.Size();
  if (n < 3) throw Error("screened_poisson_2d: needs at least 3 oriented points, got " + std::to_string(n));
  if (!pc.HasNormals()) throw Error("screened_poisson_2d: the points have no normals (oriented points needed)");
  for (int i = 0; i < n; ++i) {
    if (!pc.P.row(i).allFinite() || !pc.N.row(i).allFinite())
      throw Error("screened_poisson_2d: point " + std::to_string(i) + " has a non-finite coordinate or normal");
    if (pc.P(i, 2) != 0.0)
      throw Error("screened_poisson_2d: point " + std::to_string(i) + " has z = " + std::to_string(pc.P(i, 2)) +
                  " (2D points lie in z = 0)");
  }
  const Eigen::Vector2d lo = pc.P.leftCols<2>().colwise().minCoeff().transpose();
  const Eigen::Vector2d hi = pc.P.leftCols<2>().colwise().maxCoeff().transpose();
  const double extent = (hi - lo).maxCoeff();
  if (!(extent > 0)) throw Error("screened_poisson_2d: all points coincide (nothing to reconstruct)");

  const int res = Poisson2DResolution(options, n);
  const int m = res + 1;  // nodes per side
  const double side = options.scale * extent;
  const double h = side / res;
  const Eigen::Vector2d origin = 0.5 * (lo + hi) - Eigen::Vector2d::Constant(0.5 * side);
  auto node = [m](int i, int j) { return i + m * j; };

  // Per-point curve length a_p from the k-th nearest neighbour.
  std::vector<double> a(n);
  {
    const int k = std::min(options.neighbours, n - 1);
    MatrixX3d P3 = pc.P;
    const KdTree3 tree(P3);
    Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> knn;
    tree.KnnBatch(P3, k + 1, &knn);
    for (int i = 0; i < n; ++i) {
      double rk = 0;
      for (int c = 0; c < k + 1; ++c)
        if (knn(i, c) >= 0) rk = std::max(rk, (P3.row(knn(i, c)) - P3.row(i)).norm());
      a[i] = 2.0 * rk / k;
    }
    std::vector<double> sorted = a;
    std::nth_element(sorted.begin(), sorted.begin() + n / 2, sorted.end());
    double med = sorted[n / 2];
    if (!(med > 0)) {  // more than half the points coincide: use the mean of the others
      double s = 0;
      int c = 0;
      for (double x : a)
        if (x > 0) s += x, ++c;
      med = c > 0 ? s / c : h;
    }
    for (double& x : a) x = std::clamp(x, 0.1 * med, 10.0 * med);
  }
  ctx.CheckStop();

  // Bilinear stencil of a point in a lattice offset by (ox, oy) cells.
  struct Stencil {
    int i0, j0;
    double w[4];  // (i0,j0), (i0+1,j0), (i0,j0+1), (i0+1,j0+1)
  };
  auto stencil = [&](const Eigen::Vector2d& p, double ox, double oy, int ni, int nj) {
    const double u = (p.x() - origin.x()) / h - ox, v = (p.y() - origin.y()) / h - oy;
    Stencil s;
    s.i0 = std::clamp(static_cast<int>(std::floor(u)), 0, ni - 2);
    s.j0 = std::clamp(static_cast<int>(std::floor(v)), 0, nj - 2);
    const double fx = std::clamp(u - s.i0, 0.0, 1.0), fy = std::clamp(v - s.j0, 0.0, 1.0);
    s.w[0] = (1 - fx) * (1 - fy);
    s.w[1] = fx * (1 - fy);
    s.w[2] = (1 - fx) * fy;
    s.w[3] = fx * fy;
    return s;
  };

  // Right-hand side D^T (h V): x-edges (i,j)-(i+1,j) have midpoints at
  // (i + 1/2, j) cells, y-edges (i,j)-(i,j+1) at (i, j + 1/2). Each point's
  // inward normal -n_p a_p is spread over the edges within R_p cells by the
  // separable biweight (1 - t^2)^2, normalised to sum 1, with
  // R_p = max(1, smoothing * a_p / h): sparse points spread further, as
  // they fall into coarse octree nodes in PoissonRecon.
  VectorXd rhs = VectorXd::Zero(static_cast<Eigen::Index>(m) * m);
  {
    std::vector<double> wx, wy;
    for (int p = 0; p < n; ++p) {
      const Eigen::Vector2d x(pc.P(p, 0), pc.P(p, 1));
      const Eigen::Vector2d nrm(pc.N(p, 0), pc.N(p, 1));
      const double scale_p = -a[p] / h;  // inward normal, per cell
      const double R = std::max(1.0, options.smoothing * a[p] / h);
      for (int axis = 0; axis < 2; ++axis) {
        const double comp = scale_p * nrm[axis];
        if (comp == 0.0) continue;
        // x-edges: res x m lattice offset (1/2, 0); y-edges: m x res offset (0, 1/2).
        const int ni = axis == 0 ? res : m, nj = axis == 0 ? m : res;
        const double u = (x.x() - origin.x()) / h - (axis == 0 ? 0.5 : 0.0);
        const double v = (x.y() - origin.y()) / h - (axis == 0 ? 0.0 : 0.5);
        const int i0 = std::max(0, static_cast<int>(std::ceil(u - R))), i1 = std::min(ni - 1, static_cast<int>(std::floor(u + R)));
        const int j0 = std::max(0, static_cast<int>(std::ceil(v - R))), j1 = std::min(nj - 1, static_cast<int>(std::floor(v + R)));
        auto kernel = [R](double d) {
          const double t = d / R;
          return t * t < 1 ? (1 - t * t) * (1 - t * t) : 0.0;
        };
        wx.assign(std::max(0, i1 - i0 + 1), 0.0);
        wy.assign(std::max(0, j1 - j0 + 1), 0.0);
        double sx = 0, sy = 0;
        for (int i = i0; i <= i1; ++i) sx += wx[i - i0] = kernel(i - u);
        for (int j = j0; j <= j1; ++j) sy += wy[j - j0] = kernel(j - v);
        if (!(sx > 0 && sy > 0)) continue;
        for (int j = j0; j <= j1; ++j)
          for (int i = i0; i <= i1; ++i) {
            const double val = comp * wx[i - i0] * wy[j - j0] / (sx * sy);
            if (val == 0.0) continue;
            const int from = node(i, j), to = axis == 0 ? node(i + 1, j) : node(i, j + 1);
            rhs[to] += val;
            rhs[from] -= val;
          }
      }
    }
  }

  // System matrix: graph Laplacian (Neumann) + screening.
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(static_cast<size_t>(m) * m * 5 + static_cast<size_t>(n) * 16);
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i) {
      const int id = node(i, j);
      for (int d = 0; d < 2; ++d) {
        const int i2 = i + (d == 0), j2 = j + (d == 1);
        if (i2 >= m || j2 >= m) continue;
        const int id2 = node(i2, j2);
        trip.emplace_back(id, id, 1.0);
        trip.emplace_back(id2, id2, 1.0);
        trip.emplace_back(id, id2, -1.0);
        trip.emplace_back(id2, id, -1.0);
      }
    }
  // Screening: the same weight for every point (its mean share of the curve
  // length, in cells), so an isolated point does not pin the contour harder.
  double a_mean = 0;
  for (double x : a) a_mean += x;
  a_mean /= n;
  std::vector<Stencil> node_st(n);
  for (int p = 0; p < n; ++p) {
    node_st[p] = stencil(Eigen::Vector2d(pc.P(p, 0), pc.P(p, 1)), 0.0, 0.0, m, m);
    const double beta = options.screening * a_mean / h;
    if (beta == 0.0) continue;
    const Stencil& s = node_st[p];
    for (int c = 0; c < 4; ++c)
      for (int d = 0; d < 4; ++d)
        trip.emplace_back(node(s.i0 + (c & 1), s.j0 + (c >> 1)), node(s.i0 + (d & 1), s.j0 + (d >> 1)),
                          beta * s.w[c] * s.w[d]);
  }
  const Eigen::Index nn = static_cast<Eigen::Index>(m) * m;
  Eigen::SparseMatrix<double> A(nn, nn);
  A.setFromTriplets(trip.begin(), trip.end());
  trip.clear();
  trip.shrink_to_fit();
  if (options.screening == 0.0) {
    // Unscreened: fix the constant by a tiny identity term (the iso-value
    // below is relative, so the constant does not matter).
    for (Eigen::Index i = 0; i < nn; ++i) A.coeffRef(i, i) += 1e-9;
  }
  ctx.CheckStop();
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(A);
  if (solver.info() != Eigen::Success) throw Error("screened_poisson_2d: the sparse factorisation failed");
  const VectorXd chi = solver.solve(rhs);
  if (solver.info() != Eigen::Success || !chi.allFinite()) throw Error("screened_poisson_2d: the sparse solve failed");

  // Iso-value: the mean of χ at the points.
  double num = 0, den = 0;
  for (int p = 0; p < n; ++p) {
    const Stencil& s = node_st[p];
    double v = 0;
    for (int c = 0; c < 4; ++c) v += s.w[c] * chi[node(s.i0 + (c & 1), s.j0 + (c >> 1))];
    num += v;
    den += 1;
  }
  const double iso = num / den;
  if (info) {
    info->resolution = res;
    info->iso_value = iso;
  }
  ctx.CheckStop();

  // Marching squares takes "inside iff value < level": contour -χ at -iso.
  GridInfo g;
  g.dim = 2;
  g.dims = {m, m, 1};
  g.min = {origin.x(), origin.y(), 0.0};
  g.max = {origin.x() + side, origin.y() + side, 0.0};
  const Polyline2 contour = MarchingSquares(-chi, g, -iso);
  return ToPolyline(contour);
}

}  // namespace arcs
