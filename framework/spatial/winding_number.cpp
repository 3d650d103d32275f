// Generalized winding numbers: exact solid-angle sums and the hierarchical
// (Barill et al. 2018 style) far-field approximation.
#include "framework/spatial/winding_number.h"

#include "framework/error.h"
#include "framework/spatial/knn.h"
#include "framework/spatial/topology.h"
#include "framework/util/parallel.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

namespace arcs {
namespace {

constexpr double kInv2Pi = 0.5 / std::numbers::pi;

// Van Oosterom & Strackee (1983): tan(Omega/2) = a.(b x c) / (|a||b||c| +
// (a.b)|c| + (b.c)|a| + (c.a)|b|) with a, b, c the corners relative to q.
// Returns the numerator and denominator; Omega / (4 pi) = atan2(num, den) / (2 pi).
inline void SolidAngleTerms(double ax, double ay, double az, double bx, double by, double bz,
                            double cx, double cy, double cz, double* num, double* den) {
  const double la = std::sqrt(ax * ax + ay * ay + az * az);
  const double lb = std::sqrt(bx * bx + by * by + bz * bz);
  const double lc = std::sqrt(cx * cx + cy * cy + cz * cz);
  *num = ax * (by * cz - bz * cy) + ay * (bz * cx - bx * cz) + az * (bx * cy - by * cx);
  *den = la * lb * lc + (ax * bx + ay * by + az * bz) * lc + (bx * cx + by * cy + bz * cz) * la +
         (cx * ax + cy * ay + cz * az) * lb;
}

// Triangles as structure-of-arrays so the numerator/denominator loop vectorises.
struct TriSoa {
  std::vector<double> ax, ay, az, bx, by, bz, cx, cy, cz;
  void Resize(std::size_t n) {
    for (auto* v : {&ax, &ay, &az, &bx, &by, &bz, &cx, &cy, &cz}) v->resize(n);
  }
  void Set(std::size_t i, const Mesh& m, int f) {
    const auto a = m.V.row(m.F(f, 0)), b = m.V.row(m.F(f, 1)), c = m.V.row(m.F(f, 2));
    ax[i] = a(0), ay[i] = a(1), az[i] = a(2);
    bx[i] = b(0), by[i] = b(1), bz[i] = b(2);
    cx[i] = c(0), cy[i] = c(1), cz[i] = c(2);
  }
};

// atan2 written so that a loop over it vectorises (no libm call, selects
// instead of branches), accurate to a few ulp: reduce to t = min/max in [0, 1],
// halve the angle twice with atan(t) = 2 atan(t / (1 + sqrt(1 + t^2))) so that
// |u| <= tan(pi/16) ~ 0.199, then the Taylor series of atan up to u^21 (the
// remainder u^23 / 23 < 4e-18). Quadrant fix-up as in atan2 (atan2(0, 0) = 0).
inline double Atan2Vec(double y, double x) {
  const double ax = std::abs(x), ay = std::abs(y);
  const double mx = std::max(ax, ay), mn = std::min(ax, ay);
  const double t = mx > 0.0 ? mn / mx : 0.0;
  const double t1 = t / (1.0 + std::sqrt(1.0 + t * t));
  const double u = t1 / (1.0 + std::sqrt(1.0 + t1 * t1));
  const double u2 = u * u;
  // atan(u) = u + u * z * P(z), z = u^2, P(z) = sum_{k=1..10} (-1)^k z^(k-1) / (2k+1).
  double p = 1.0 / 21.0;
  p = p * u2 - 1.0 / 19.0;
  p = p * u2 + 1.0 / 17.0;
  p = p * u2 - 1.0 / 15.0;
  p = p * u2 + 1.0 / 13.0;
  p = p * u2 - 1.0 / 11.0;
  p = p * u2 + 1.0 / 9.0;
  p = p * u2 - 1.0 / 7.0;
  p = p * u2 + 1.0 / 5.0;
  p = p * u2 - 1.0 / 3.0;
  double a = 4.0 * (u + u * (u2 * p));
  a = ay > ax ? 0.5 * std::numbers::pi - a : a;
  a = x < 0.0 ? std::numbers::pi - a : a;
  return y < 0.0 ? -a : a;
}

// Sum of solid angles / (4 pi) of triangles [begin, end) seen from q, in
// blocks: the vectorisable part per triangle into a buffer, then a sequential
// (deterministic) sum.
double SumSolidAngles(const TriSoa& t, std::size_t begin, std::size_t end, const double* q) {
  constexpr std::size_t kBlock = 64;
  double ang[kBlock];
  double sum = 0.0;
  const double qx = q[0], qy = q[1], qz = q[2];
  for (std::size_t s = begin; s < end; s += kBlock) {
    const std::size_t n = std::min(kBlock, end - s);
    const double* ax = t.ax.data() + s;
    const double* ay = t.ay.data() + s;
    const double* az = t.az.data() + s;
    const double* bx = t.bx.data() + s;
    const double* by = t.by.data() + s;
    const double* bz = t.bz.data() + s;
    const double* cx = t.cx.data() + s;
    const double* cy = t.cy.data() + s;
    const double* cz = t.cz.data() + s;
    for (std::size_t i = 0; i < n; ++i) {
      double num, den;
      SolidAngleTerms(ax[i] - qx, ay[i] - qy, az[i] - qz, bx[i] - qx, by[i] - qy, bz[i] - qz,
                      cx[i] - qx, cy[i] - qy, cz[i] - qz, &num, &den);
      ang[i] = Atan2Vec(num, den);
    }
    for (std::size_t i = 0; i < n; ++i) sum += ang[i];
  }
  return sum * kInv2Pi;
}

}  // namespace

double TriangleSolidAngleOver4Pi(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& q) {
  double num, den;
  SolidAngleTerms(a.x() - q.x(), a.y() - q.y(), a.z() - q.z(), b.x() - q.x(), b.y() - q.y(),
                  b.z() - q.z(), c.x() - q.x(), c.y() - q.y(), c.z() - q.z(), &num, &den);
  return std::atan2(num, den) * kInv2Pi;
}

double WindingNumberExact(const Mesh& mesh, const Vec3& q) {
  CheckMeshIndices(mesh, "WindingNumberExact", /*finite=*/true);
  TriSoa t;
  t.Resize(mesh.NumFaces());
  for (int f = 0; f < mesh.NumFaces(); ++f) t.Set(f, mesh, f);
  const double p[3] = {q.x(), q.y(), q.z()};
  return SumSolidAngles(t, 0, mesh.NumFaces(), p);
}

VectorXd WindingNumbersExact(const Mesh& mesh, const MatrixX3d& Q) {
  CheckMeshIndices(mesh, "WindingNumbersExact", /*finite=*/true);
  TriSoa t;
  t.Resize(mesh.NumFaces());
  for (int f = 0; f < mesh.NumFaces(); ++f) t.Set(f, mesh, f);
  VectorXd w(Q.rows());
  const std::size_t nf = mesh.NumFaces();
  ParallelFor(
      Q.rows(),
      [&](std::int64_t begin, std::int64_t end) {
        for (std::int64_t i = begin; i < end; ++i) {
          const double p[3] = {Q(i, 0), Q(i, 1), Q(i, 2)};
          w[i] = SumSolidAngles(t, 0, nf, p);
        }
      },
      // About 2e5 triangle-query pairs per task.
      std::max<std::int64_t>(1, 200000 / std::max<std::int64_t>(1, static_cast<std::int64_t>(nf))));
  return w;
}

// ---------------------------------------------------------------------------
// Hierarchical winding number.
//
// Far field (Barill et al. 2018, sec. 3.2): w(q) = sum_t integral_t n_t . f(x)
// dA with f(x) = (x - q) / (4 pi |x - q|^3), f expanded about the cluster
// centre p (area-weighted centroid), r = p - q:
//   w ~= N . f(p) + grad f(p) : M + 1/2 grad^2 f(p) : C,
//   N = sum_t A_t n_t,  M = sum_t A_t (x_t - p) n_t^T  (x_t the centroid: exact
//   first moment), C_ijk = sum_t A_t n_{t,i} <(x-p)_j (x-p)_k>_t (exact second
//   moments of the triangles).
// The cluster is accepted when |r| > beta * radius. Measured worst case (the
// centre of a sphere): max |dw| 5e-3 at beta 2, 1.7e-4 at beta 4.

namespace {

struct FwnNode {
  double centre[3];
  double radius;  // max distance from centre to any corner in the cluster
  double n[3];    // area-weighted normal sum (A_t n_t = cross / 2)
  double m[9];    // first moments, row-major m[3*i+j] = sum_t A_t (x_t-p)_i n_{t,j}
  // Second moments C_ijk = sum_t A_t n_{t,i} <(x-p)_j (x-p)_k>_t (average over
  // triangle t), stored per i as a symmetric 3x3 (xx, xy, xz, yy, yz, zz), and
  // the contractions cw_k = sum_i C_iik, cz_i = sum_j C_ijj.
  double c[18];
  double cw[3], cz[3];
  std::int32_t first, count;  // leaf: triangle range; inner: count = 0, children first, first+1
};

constexpr int kFwnLeaf = 8;

}  // namespace

void FastWindingNumberOptions::Check() const {
  ARCS_CHECK_OPTION(std::isfinite(beta) && beta >= 1.0, "beta", beta, "a finite number >= 1");
  ARCS_CHECK_OPTION(expansion_order >= 0 && expansion_order <= 2, "expansion_order", expansion_order,
                    "0, 1 or 2");
}

struct FastWindingNumber::Impl {
  Options options;
  std::vector<FwnNode> nodes;
  TriSoa tris;  // leaf order
  double Eval(const double* q) const;
};

FastWindingNumber::FastWindingNumber(const Mesh& mesh, const Options& options)
    : impl_(std::make_unique<Impl>()) {
  options.Check();
  CheckMeshIndices(mesh, "FastWindingNumber", /*finite=*/true);
  impl_->options = options;
  const int nf = mesh.NumFaces();
  std::vector<Vec3> centroid(nf), an(nf);
  std::vector<double> area(nf);
  for (int f = 0; f < nf; ++f) {
    const Vec3 a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)),
               c = mesh.V.row(mesh.F(f, 2));
    centroid[f] = (a + b + c) / 3.0;
    an[f] = 0.5 * (b - a).cross(c - a);
    area[f] = an[f].norm();
  }
  std::vector<std::int32_t> order(nf);
  for (int f = 0; f < nf; ++f) order[f] = f;
  auto& nodes = impl_->nodes;
  nodes.reserve(2 * std::max(1, nf / kFwnLeaf + 1));
  if (nf == 0) {
    impl_->tris.Resize(0);
    return;
  }
  // Median split along the longest axis of the centroid bounds.
  struct Task {
    int node, begin, end;
  };
  std::vector<Task> stack{{0, 0, nf}};
  nodes.emplace_back();
  while (!stack.empty()) {
    const Task t = stack.back();
    stack.pop_back();
    Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
    for (int i = t.begin; i < t.end; ++i) {
      lo = lo.cwiseMin(centroid[order[i]]);
      hi = hi.cwiseMax(centroid[order[i]]);
    }
    if (t.end - t.begin <= kFwnLeaf) {
      nodes[t.node].first = t.begin;
      nodes[t.node].count = t.end - t.begin;
      continue;
    }
    int axis;
    (hi - lo).maxCoeff(&axis);
    const int mid = (t.begin + t.end) / 2;
    std::nth_element(order.begin() + t.begin, order.begin() + mid, order.begin() + t.end,
                     [&](int a, int b) {
                       const double ca = centroid[a][axis], cb = centroid[b][axis];
                       return ca < cb || (ca == cb && a < b);
                     });
    const int left = static_cast<int>(nodes.size());
    nodes.emplace_back();
    nodes.emplace_back();
    nodes[t.node].first = left;
    nodes[t.node].count = 0;
    stack.push_back({left + 1, mid, t.end});
    stack.push_back({left, t.begin, mid});
  }
  impl_->tris.Resize(nf);
  for (int i = 0; i < nf; ++i) impl_->tris.Set(i, mesh, order[i]);
  // Cluster moments; children always have larger indices than their parent,
  // but moments are computed directly over each node's triangle range, which
  // is contiguous (O(F log F) in total).
  std::vector<std::pair<int, int>> range(nodes.size());
  {
    // Recover ranges: a leaf has its range; an inner node spans its children.
    for (int i = static_cast<int>(nodes.size()) - 1; i >= 0; --i) {
      if (nodes[i].count > 0) {
        range[i] = {nodes[i].first, nodes[i].first + nodes[i].count};
      } else {
        range[i] = {range[nodes[i].first].first, range[nodes[i].first + 1].second};
      }
    }
  }
  // Moments bottom-up (O(F)): a leaf's from its triangles, an inner node's
  // from its two children's, shifted from the child's centre p_c to its own
  // p (d = p_c - p, (x - p) = (x - p_c) + d):
  //   m  = sum_c m_c + d n_c^T,
  //   C_i = sum_c C_c,i + g_c,i d^T + d g_c,i^T + n_c,i d d^T, g_c,i = column i of m_c,
  // exact in exact arithmetic (the per-triangle average of (x-p)(x-p)^T is a
  // quadratic in p). Children have larger indices than their parent, so the
  // inner nodes are combined in decreasing index order after the leaves.
  // The radius is the exact maximal corner distance over the node's range.
  struct Sums {
    double asum = 0.0;
    int count = 0;
    Vec3 p = Vec3::Zero(), csum = Vec3::Zero(), nsum = Vec3::Zero();
    Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
    Eigen::Matrix3d cm[3] = {Eigen::Matrix3d::Zero(), Eigen::Matrix3d::Zero(), Eigen::Matrix3d::Zero()};
  };
  std::vector<Sums> sums(nodes.size());
  ParallelFor(static_cast<std::int64_t>(nodes.size()), [&](std::int64_t k0, std::int64_t k1) {
    for (std::int64_t k = k0; k < k1; ++k) {
      FwnNode& nd = nodes[k];
      const auto [b, e] = range[k];
      double r2 = 0.0;
      if (nd.count == 0) {
        nd.radius = -1.0;  // inner: the radius needs the centre, set below
        continue;
      }
      Sums& S = sums[k];
      for (int i = b; i < e; ++i) {
        const int f = order[i];
        S.asum += area[f];
        S.p += area[f] * centroid[f];
        S.csum += centroid[f];
        S.nsum += an[f];
      }
      S.count = e - b;
      S.p = S.asum > 0.0 ? Vec3(S.p / S.asum) : Vec3(S.csum / S.count);
      const Vec3& p = S.p;
      for (int i = b; i < e; ++i) {
        const int f = order[i];
        S.m += (centroid[f] - p) * an[f].transpose();
        // Second moment of the triangle about p: integral of d d^T over the
        // triangle = A / 12 (sum_v v v^T + s s^T), v the corners - p, s their sum.
        Vec3 v[3];
        for (int c = 0; c < 3; ++c) v[c] = mesh.V.row(mesh.F(f, c)).transpose() - p;
        const Vec3 sv = v[0] + v[1] + v[2];
        const Eigen::Matrix3d T =
            (v[0] * v[0].transpose() + v[1] * v[1].transpose() + v[2] * v[2].transpose() + sv * sv.transpose()) /
            12.0;
        for (int c = 0; c < 3; ++c) S.cm[c] += an[f][c] * T;
        for (int c = 0; c < 3; ++c) r2 = std::max(r2, v[c].squaredNorm());
      }
      nd.radius = std::sqrt(r2);
    }
  }, 64);
  for (std::int64_t k = static_cast<std::int64_t>(nodes.size()) - 1; k >= 0; --k) {
    if (nodes[k].count > 0) continue;
    Sums& S = sums[k];
    const Sums* kid[2] = {&sums[nodes[k].first], &sums[nodes[k].first + 1]};
    Vec3 wp = Vec3::Zero();
    for (const Sums* c : kid) {
      S.asum += c->asum;
      S.count += c->count;
      S.csum += c->csum;
      S.nsum += c->nsum;
      wp += c->asum * c->p;
    }
    S.p = S.asum > 0.0 ? Vec3(wp / S.asum) : Vec3(S.csum / S.count);
    for (const Sums* c : kid) {
      const Vec3 d = c->p - S.p;
      S.m += c->m + d * c->nsum.transpose();
      const Eigen::Matrix3d dd = d * d.transpose();
      for (int i = 0; i < 3; ++i) {
        const Vec3 g = c->m.col(i);
        S.cm[i] += c->cm[i] + g * d.transpose() + d * g.transpose() + c->nsum[i] * dd;
      }
    }
  }
  // Exact radii of the inner nodes about their centres (a pass over each
  // node's corner range, parallel), then the stored form.
  ParallelFor(static_cast<std::int64_t>(nodes.size()), [&](std::int64_t k0, std::int64_t k1) {
    for (std::int64_t k = k0; k < k1; ++k) {
      FwnNode& nd = nodes[k];
      const Sums& S = sums[k];
      const Vec3& p = S.p;
      if (nd.count == 0) {
        const auto [b, e] = range[k];
        double r2 = 0.0;
        for (int i = b; i < e; ++i) {
          const int f = order[i];
          for (int c = 0; c < 3; ++c) r2 = std::max(r2, (mesh.V.row(mesh.F(f, c)).transpose() - p).squaredNorm());
        }
        nd.radius = std::sqrt(r2);
      }
      for (int c = 0; c < 3; ++c) nd.centre[c] = p[c], nd.n[c] = S.nsum[c];
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) nd.m[3 * i + j] = S.m(i, j);
      for (int i = 0; i < 3; ++i) {
        const Eigen::Matrix3d& C = S.cm[i];
        double* ci = nd.c + 6 * i;
        ci[0] = C(0, 0), ci[1] = C(0, 1), ci[2] = C(0, 2), ci[3] = C(1, 1), ci[4] = C(1, 2), ci[5] = C(2, 2);
        nd.cz[i] = C.trace();
      }
      for (int k2 = 0; k2 < 3; ++k2) nd.cw[k2] = S.cm[0](0, k2) + S.cm[1](1, k2) + S.cm[2](2, k2);
    }
  }, 64);
}

FastWindingNumber::~FastWindingNumber() = default;
FastWindingNumber::FastWindingNumber(FastWindingNumber&&) noexcept = default;
FastWindingNumber& FastWindingNumber::operator=(FastWindingNumber&&) noexcept = default;

double FastWindingNumber::Impl::Eval(const double* q) const {
  if (nodes.empty()) return 0.0;
  const double beta2 = options.beta * options.beta;
  const int order = options.expansion_order;
  constexpr double kInv4Pi = 0.25 / std::numbers::pi;
  int stack[128];
  int sp = 0;
  stack[sp++] = 0;
  double far = 0.0, near = 0.0;
  while (sp > 0) {
    const FwnNode& nd = nodes[stack[--sp]];
    const double rx = nd.centre[0] - q[0], ry = nd.centre[1] - q[1], rz = nd.centre[2] - q[2];
    const double d2 = rx * rx + ry * ry + rz * rz;
    if (d2 > beta2 * nd.radius * nd.radius) {
      const double inv_d2 = 1.0 / d2;
      const double inv_d3 = std::sqrt(inv_d2) * inv_d2;
      const double r[3] = {rx, ry, rz};
      // Kernel f(x) = (x - q) / |x - q|^3 expanded about the centre p, r = p - q.
      // Order 0: N . r / |r|^3.
      double w = (nd.n[0] * rx + nd.n[1] * ry + nd.n[2] * rz) * inv_d3;
      if (order >= 1) {
        // Order 1: grad f : M = trace(M) / |r|^3 - 3 r^T M r / |r|^5.
        double rmr = 0.0;
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) rmr += r[i] * nd.m[3 * i + j] * r[j];
        w += (nd.m[0] + nd.m[4] + nd.m[8]) * inv_d3 - 3.0 * rmr * inv_d3 * inv_d2;
      }
      if (order >= 2) {
        // Order 2: 1/2 d2f : C with d_j d_k f_i = -3 (delta_ij r_k + delta_ik r_j +
        // delta_jk r_i) / |r|^5 + 15 r_i r_j r_k / |r|^7.
        const double v1 = nd.cw[0] * rx + nd.cw[1] * ry + nd.cw[2] * rz;
        const double v2 = nd.cz[0] * rx + nd.cz[1] * ry + nd.cz[2] * rz;
        double v3 = 0.0;
        for (int i = 0; i < 3; ++i) {
          const double* S = nd.c + 6 * i;
          const double rsr = S[0] * rx * rx + S[3] * ry * ry + S[5] * rz * rz +
                             2.0 * (S[1] * rx * ry + S[2] * rx * rz + S[4] * ry * rz);
          v3 += r[i] * rsr;
        }
        const double inv_d5 = inv_d3 * inv_d2;
        w += 0.5 * (-3.0 * inv_d5 * (2.0 * v1 + v2) + 15.0 * inv_d5 * inv_d2 * v3);
      }
      far += w * kInv4Pi;
    } else if (nd.count > 0) {
      near += SumSolidAngles(tris, nd.first, nd.first + nd.count, q);
    } else {
      stack[sp++] = nd.first + 1;
      stack[sp++] = nd.first;
    }
  }
  return far + near;
}

double FastWindingNumber::Eval(const Vec3& q) const {
  const double p[3] = {q.x(), q.y(), q.z()};
  return impl_->Eval(p);
}

VectorXd FastWindingNumber::Eval(const MatrixX3d& Q) const {
  VectorXd w(Q.rows());
  // Morton order: neighbouring queries open the same clusters (cache reuse).
  const std::vector<int> order = MortonOrder(Q);
  ParallelFor(
      Q.rows(),
      [&](std::int64_t begin, std::int64_t end) {
        for (std::int64_t s = begin; s < end; ++s) {
          const std::int64_t i = order[s];
          const double p[3] = {Q(i, 0), Q(i, 1), Q(i, 2)};
          w[i] = impl_->Eval(p);
        }
      },
      256);
  return w;
}

}  // namespace arcs
