// Winding-number voxelization; see voxelize.h and docs/voxelization.md.
#include "framework/voxel/voxelize.h"

#include "framework/error.h"
#include "framework/spatial/topology.h"
#include "framework/spatial/triangle_bvh.h"
#include "framework/spatial/winding_number.h"
#include "framework/util/parallel.h"
#include "framework/util/rng.h"
#include "framework/voxel/ray_parity.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <initializer_list>
#include <memory>
#include <cmath>
#include <numbers>
#include <unordered_map>

namespace arcs {

GridInfo CubeGrid(int resolution, const Vec3& lo, const Vec3& hi) {
  ARCS_CHECK_OPTION(resolution >= 2, "resolution", resolution, "an integer >= 2");
  GridInfo g;
  g.dim = 3;
  for (int a = 0; a < 3; ++a) {
    if (!(std::isfinite(lo[a]) && std::isfinite(hi[a]) && lo[a] < hi[a]))
      throw OptionError("grid bounds must be finite with lo < hi on every axis (axis " + std::to_string(a) +
                        ": lo " + std::to_string(lo[a]) + ", hi " + std::to_string(hi[a]) + ")");
    g.dims[a] = resolution;
    g.min[a] = lo[a];
    g.max[a] = hi[a];
  }
  return g;
}

double GridCoord(const GridInfo& g, int axis, int i) {
  const int n = g.dims[axis];
  if (n <= 1) return g.min[axis];
  if (i == n - 1) return g.max[axis];
  return g.min[axis] + i * ((g.max[axis] - g.min[axis]) / (n - 1));
}

MatrixX3d GridNodes(const GridInfo& g) {
  MatrixX3d Q(g.NumNodes(), 3);
  const int nx = g.dims[0], ny = g.dims[1], nz = g.dims[2];
  std::int64_t r = 0;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i, ++r) Q.row(r) << GridCoord(g, 0, i), GridCoord(g, 1, j), GridCoord(g, 2, k);
  return Q;
}

namespace {

// floor/ceil of a grid position, clamped to [lo, hi] before the cast to int:
// a coordinate far outside the grid (1e300 / h) or a NaN position must not
// reach static_cast<int> (undefined beyond the int range).
inline int ClampIndex(double x, int lo, int hi) {
  if (!(x > lo)) return lo;
  if (x >= hi) return hi;
  return static_cast<int>(x);
}
void CheckChoice(const std::string& name, const std::string& v, std::initializer_list<const char*> ok) {
  std::string list;
  for (const char* c : ok) {
    if (v == c) return;
    list += (list.empty() ? "" : ", ") + std::string(c);
  }
  throw OptionError(name + " = '" + v + "': must be one of " + list);
}
}  // namespace

void VoxelizeOptions::Check() const {
  CheckChoice("method", method, {"exact", "fast", "naive", "ray_parity"});
  CheckChoice("output", output, {"occupancy", "winding"});
  CheckChoice("open_mesh", open_mesh, {"auto", "none", "flip_dup"});
  CheckChoice("orientation", orientation, {"abs", "as_is"});
  // Sane caps: the voxelize stage and `arcs voxelize` declare the same bounds.
  ARCS_CHECK_OPTION(epsilon >= 0.0 && epsilon <= 1e9, "epsilon", epsilon, "in [0, 1e9]");
  ARCS_CHECK_OPTION(beta >= 1.0 && beta <= 1e9, "beta", beta, "in [1, 1e9]");
  ARCS_CHECK_OPTION(std::isfinite(exact_band) && exact_band >= 0.0 && exact_band <= 0.5, "exact_band", exact_band,
                    "a number in [0, 0.5]");
}

Mesh DropDegenerateFaces(const Mesh& mesh, std::int64_t* dropped) {
  Mesh out;
  out.V = mesh.V;
  std::vector<int> keep;
  keep.reserve(mesh.NumFaces());
  for (int f = 0; f < mesh.NumFaces(); ++f) {
    const int a = mesh.F(f, 0), b = mesh.F(f, 1), c = mesh.F(f, 2);
    if (a == b || b == c || a == c) continue;
    const Vec3 n = (mesh.V.row(b) - mesh.V.row(a)).transpose().cross((mesh.V.row(c) - mesh.V.row(a)).transpose());
    if (n.x() == 0.0 && n.y() == 0.0 && n.z() == 0.0) continue;
    keep.push_back(f);
  }
  out.F.resize(static_cast<int>(keep.size()), 3);
  for (std::size_t i = 0; i < keep.size(); ++i) out.F.row(static_cast<int>(i)) = mesh.F.row(keep[i]);
  if (dropped) *dropped = mesh.NumFaces() - static_cast<std::int64_t>(keep.size());
  return out;
}

std::int64_t CountUnbalancedEdges(const Mesh& mesh) {
  // Net count per undirected edge: +1 for a->b with a < b, -1 for b->a.
  std::unordered_map<std::uint64_t, int> net;
  net.reserve(static_cast<std::size_t>(mesh.NumFaces()) * 2);
  for (int f = 0; f < mesh.NumFaces(); ++f)
    for (int c = 0; c < 3; ++c) {
      const std::uint32_t a = static_cast<std::uint32_t>(mesh.F(f, c));
      const std::uint32_t b = static_cast<std::uint32_t>(mesh.F(f, (c + 1) % 3));
      if (a == b) continue;
      const std::uint64_t key = a < b ? (std::uint64_t(a) << 32 | b) : (std::uint64_t(b) << 32 | a);
      net[key] += a < b ? 1 : -1;
    }
  std::int64_t n = 0;
  for (const auto& [k, v] : net) n += v != 0;
  return n;
}

Mesh FlipDuplicate(const Mesh& mesh, double epsilon) {
  const int nv = mesh.NumVertices(), nf = mesh.NumFaces();
  MatrixX3d N = MatrixX3d::Zero(nv, 3);
  for (int f = 0; f < nf; ++f) {
    const Vec3 a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)), c = mesh.V.row(mesh.F(f, 2));
    const Vec3 n = (b - a).cross(c - a);  // area-weighted (2A n)
    for (int k = 0; k < 3; ++k) N.row(mesh.F(f, k)) += n.transpose();
  }
  Mesh out;
  out.V.resize(2 * nv, 3);
  out.F.resize(2 * nf, 3);
  out.V.topRows(nv) = mesh.V;
  for (int v = 0; v < nv; ++v) {
    const double len = N.row(v).norm();
    out.V.row(nv + v) = mesh.V.row(v);
    if (len > 0.0) out.V.row(nv + v) -= (epsilon / len) * N.row(v);
  }
  out.F.topRows(nf) = mesh.F;
  for (int f = 0; f < nf; ++f) out.F.row(nf + f) << nv + mesh.F(f, 0), nv + mesh.F(f, 2), nv + mesh.F(f, 1);
  return out;
}

VectorXd WindingNumbersNaive(const Mesh& mesh, const MatrixX3d& Q) {
  CheckMeshIndices(mesh, "WindingNumbersNaive", /*finite=*/true);
  const int nf = mesh.NumFaces();
  // Per face: centroid c and area-weighted normal A n = cross / 2.
  std::vector<double> cx(nf), cy(nf), cz(nf), nx(nf), ny(nf), nz(nf);
  for (int f = 0; f < nf; ++f) {
    const Vec3 a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)), c = mesh.V.row(mesh.F(f, 2));
    const Vec3 ce = (a + b + c) / 3.0, n = 0.5 * (b - a).cross(c - a);
    cx[f] = ce.x(), cy[f] = ce.y(), cz[f] = ce.z(), nx[f] = n.x(), ny[f] = n.y(), nz[f] = n.z();
  }
  VectorXd w(Q.rows());
  ParallelFor(
      Q.rows(),
      [&](std::int64_t b, std::int64_t e) {
        for (std::int64_t i = b; i < e; ++i) {
          const double qx = Q(i, 0), qy = Q(i, 1), qz = Q(i, 2);
          double s = 0.0;
          for (int f = 0; f < nf; ++f) {
            const double rx = cx[f] - qx, ry = cy[f] - qy, rz = cz[f] - qz;
            const double d2 = rx * rx + ry * ry + rz * rz;
            const double t = (nx[f] * rx + ny[f] * ry + nz[f] * rz) / (d2 * std::sqrt(d2));
            s += d2 > 0.0 ? t : 0.0;
          }
          w[i] = s * (0.25 / std::numbers::pi);
        }
      },
      std::max<std::int64_t>(1, 200000 / std::max(1, nf)));
  return w;
}

Mesh PunchHoles(const Mesh& mesh, const std::vector<Vec3>& centres, double radius) {
  std::vector<int> keep;
  const double r2 = radius * radius;
  for (int f = 0; f < mesh.NumFaces(); ++f) {
    bool hit = false;
    for (int c = 0; c < 3 && !hit; ++c)
      for (const Vec3& p : centres)
        if ((mesh.V.row(mesh.F(f, c)).transpose() - p).squaredNorm() <= r2) {
          hit = true;
          break;
        }
    if (!hit) keep.push_back(f);
  }
  Mesh out;
  out.V = mesh.V;
  out.F.resize(static_cast<int>(keep.size()), 3);
  for (std::size_t i = 0; i < keep.size(); ++i) out.F.row(static_cast<int>(i)) = mesh.F.row(keep[i]);
  return out;
}

std::vector<Vec3> SpreadVertices(const Mesh& mesh, int count) {
  std::vector<Vec3> out;
  const int nv = mesh.NumVertices();
  if (nv == 0 || count <= 0) return out;
  std::vector<double> d(nv, INFINITY);
  int next = 0;
  for (int s = 0; s < count && s < nv; ++s) {
    const Vec3 p = mesh.V.row(next);
    out.push_back(p);
    int best = 0;
    for (int v = 0; v < nv; ++v) {
      d[v] = std::min(d[v], (mesh.V.row(v).transpose() - p).squaredNorm());
      if (d[v] > d[best]) best = v;
    }
    next = best;
  }
  return out;
}

namespace {

std::int64_t NodeIndex(const GridInfo& g, int i, int j, int k) {
  return i + static_cast<std::int64_t>(g.dims[0]) * (j + static_cast<std::int64_t>(g.dims[1]) * k);
}

// Nodes of z-slab k as rows.
MatrixX3d SlabNodes(const GridInfo& g, int k) {
  const int nx = g.dims[0], ny = g.dims[1];
  MatrixX3d Q(static_cast<std::int64_t>(nx) * ny, 3);
  const double z = GridCoord(g, 2, k);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) Q.row(i + static_cast<std::int64_t>(nx) * j) << GridCoord(g, 0, i), GridCoord(g, 1, j), z;
  return Q;
}

// The winding number at the rows of Q by one of the sums.
enum class Sum { kExact, kNaive, kFast };

double Orient(double w, bool abs) { return abs ? std::abs(w) : w; }

// ---------------------------------------------------------------------------
// Flood fill for balanced meshes.
//
// cut[n] bit a (a = 0, 1, 2): the grid edge from node n to its +a neighbour
// may be crossed by a triangle. Marking is conservative (tolerances far above
// the rounding error of the tests), so an unmarked edge is a segment that no
// triangle touches, and w (locally constant off the surface of a balanced
// mesh) is equal at its two ends.
void MarkCrossings(const Mesh& mesh, const GridInfo& g, std::vector<std::uint8_t>* cut) {
  Vec3 lo = mesh.V.colwise().minCoeff().transpose(), hi = mesh.V.colwise().maxCoeff().transpose();
  const double L = std::max((hi - lo).norm(), 1e-300);
  const double tol_l = 1e-9 * L;
  const std::int64_t stride[3] = {1, g.dims[0], static_cast<std::int64_t>(g.dims[0]) * g.dims[1]};
  double h[3];
  for (int a = 0; a < 3; ++a) h[a] = (g.max[a] - g.min[a]) / (g.dims[a] - 1);
  std::uint8_t* c = cut->data();
  for (int f = 0; f < mesh.NumFaces(); ++f) {
    double P[3][3];
    for (int v = 0; v < 3; ++v)
      for (int a = 0; a < 3; ++a) P[v][a] = mesh.V(mesh.F(f, v), a);
    double tmin[3], tmax[3];
    for (int a = 0; a < 3; ++a) {
      tmin[a] = std::min({P[0][a], P[1][a], P[2][a]});
      tmax[a] = std::max({P[0][a], P[1][a], P[2][a]});
    }
    const Vec3 e1(P[1][0] - P[0][0], P[1][1] - P[0][1], P[1][2] - P[0][2]);
    const Vec3 e2(P[2][0] - P[0][0], P[2][1] - P[0][1], P[2][2] - P[0][2]);
    const double n3 = e1.cross(e2).norm();
    const double lt = std::sqrt((tmax[0] - tmin[0]) * (tmax[0] - tmin[0]) + (tmax[1] - tmin[1]) * (tmax[1] - tmin[1]) +
                                (tmax[2] - tmin[2]) * (tmax[2] - tmin[2])) +
                      tol_l;
    const double tol_e = 1e-10 * lt * lt;
    for (int a = 0; a < 3; ++a) {
      const int u = (a + 1) % 3, v = (a + 2) % 3;
      const double pu[3] = {P[0][u], P[1][u], P[2][u]}, pv[3] = {P[0][v], P[1][v], P[2][v]};
      const double pa[3] = {P[0][a], P[1][a], P[2][a]};
      const double area2 = (pu[1] - pu[0]) * (pv[2] - pv[0]) - (pv[1] - pv[0]) * (pu[2] - pu[0]);
      const double s = area2 >= 0.0 ? 1.0 : -1.0;
      const bool conditioned = std::abs(area2) >= 1e-3 * n3 && std::abs(area2) > 0.0;
      const double tol_t = 1e-9 * L + (conditioned ? 1e-10 * lt * lt * lt / std::abs(area2) : 0.0);
      const int j0 = ClampIndex(std::floor((tmin[u] - tol_l - g.min[u]) / h[u]), 0, g.dims[u]);
      const int j1 = ClampIndex(std::ceil((tmax[u] + tol_l - g.min[u]) / h[u]), -1, g.dims[u] - 1);
      const int k0 = ClampIndex(std::floor((tmin[v] - tol_l - g.min[v]) / h[v]), 0, g.dims[v]);
      const int k1 = ClampIndex(std::ceil((tmax[v] + tol_l - g.min[v]) / h[v]), -1, g.dims[v] - 1);
      for (int j = j0; j <= j1; ++j) {
        const double U = GridCoord(g, u, j);
        if (U < tmin[u] - tol_l || U > tmax[u] + tol_l) continue;
        for (int k = k0; k <= k1; ++k) {
          const double V = GridCoord(g, v, k);
          if (V < tmin[v] - tol_l || V > tmax[v] + tol_l) continue;
          const double ea = (pu[1] - pu[0]) * (V - pv[0]) - (pv[1] - pv[0]) * (U - pu[0]);  // edge 0-1
          const double eb = (pu[2] - pu[1]) * (V - pv[1]) - (pv[2] - pv[1]) * (U - pu[1]);  // edge 1-2
          const double ec = (pu[0] - pu[2]) * (V - pv[2]) - (pv[0] - pv[2]) * (U - pu[2]);  // edge 2-0
          if (s * ea < -tol_e || s * eb < -tol_e || s * ec < -tol_e) continue;
          double tlo = tmin[a] - tol_l, thi = tmax[a] + tol_l;
          if (conditioned) {
            // Barycentric weights: vertex 1 <-> edge 2-0, vertex 2 <-> edge 0-1.
            const double t = pa[0] + (ec / area2) * (pa[1] - pa[0]) + (ea / area2) * (pa[2] - pa[0]);
            tlo = std::max(tlo, t - tol_t);
            thi = std::min(thi, t + tol_t);
          }
          // Edges i (from node i to i + 1 along a) meeting [tlo, thi].
          const int na = g.dims[a];
          int i0 = ClampIndex(std::floor((tlo - g.min[a]) / h[a]) - 1, 0, na - 1);
          int i1 = ClampIndex(std::floor((thi - g.min[a]) / h[a]) + 1, -1, na - 2);
          while (i0 <= i1 && GridCoord(g, a, i0 + 1) < tlo) ++i0;
          while (i1 >= i0 && GridCoord(g, a, i1) > thi) --i1;
          if (i0 > i1) continue;
          int idx[3];
          idx[u] = j, idx[v] = k, idx[a] = i0;
          std::int64_t n = NodeIndex(g, idx[0], idx[1], idx[2]);
          for (int i = i0; i <= i1; ++i, n += stride[a]) c[n] |= static_cast<std::uint8_t>(1u << a);
        }
      }
    }
  }
}

}  // namespace

namespace {

struct Evaluator {
  Sum sum;
  const Mesh* mesh;
  const FastWindingNumber* fwn;
  VectorXd Eval(const MatrixX3d& Q) const {
    switch (sum) {
      case Sum::kExact: return WindingNumbersExact(*mesh, Q);
      case Sum::kNaive: return WindingNumbersNaive(*mesh, Q);
      case Sum::kFast: return fwn->Eval(Q);
    }
    return {};
  }
};

// w at every node (orientation applied) by the hierarchy (+ exact band), the
// exact or the naive sum, slab by slab (bounded memory).
VectorXd SlabWinding(const Mesh& mesh, const GridInfo& g, Sum sum, const VoxelizeOptions& o, bool abs,
                     std::int64_t* exact_evals) {
  std::unique_ptr<FastWindingNumber> fwn;
  if (sum == Sum::kFast) {
    FastWindingNumber::Options fo;
    fo.beta = o.beta;
    fwn = std::make_unique<FastWindingNumber>(mesh, fo);
  }
  const std::int64_t slab = static_cast<std::int64_t>(g.dims[0]) * g.dims[1];
  VectorXd w(g.NumNodes());
  const Evaluator ev{sum, &mesh, fwn.get()};
  for (int k = 0; k < g.dims[2]; ++k) {
    const MatrixX3d Q = SlabNodes(g, k);
    VectorXd wk = ev.Eval(Q);
    if (sum == Sum::kFast && o.exact_band > 0.0) {
      std::vector<std::int64_t> redo;
      for (std::int64_t r = 0; r < wk.size(); ++r)
        if (std::abs(Orient(wk[r], abs) - 0.5) < o.exact_band) redo.push_back(r);
      if (!redo.empty()) {
        MatrixX3d R(static_cast<std::int64_t>(redo.size()), 3);
        for (std::size_t i = 0; i < redo.size(); ++i) R.row(static_cast<std::int64_t>(i)) = Q.row(redo[i]);
        const VectorXd we = WindingNumbersExact(mesh, R);
        for (std::size_t i = 0; i < redo.size(); ++i) wk[redo[i]] = we[static_cast<std::int64_t>(i)];
        *exact_evals += static_cast<std::int64_t>(redo.size());
      }
    }
    for (std::int64_t r = 0; r < slab; ++r) w[k * slab + r] = Orient(wk[r], abs);
  }
  return w;
}

// Flood-fill path (balanced mesh): exact w per component.
VectorXd FloodWinding(const Mesh& mesh, const GridInfo& g, bool abs, VoxelizeReport* rep) {
  const std::int64_t n = g.NumNodes();
  std::vector<std::uint8_t> cut(n, 0);
  MarkCrossings(mesh, g, &cut);
  const int nx = g.dims[0], ny = g.dims[1], nz = g.dims[2];
  const std::int64_t sy = nx, sz = static_cast<std::int64_t>(nx) * ny;
  std::vector<std::int32_t> label(n, -1);
  std::vector<std::int64_t> rep_node;
  std::vector<std::int64_t> queue;
  queue.reserve(1 << 16);
  for (std::int64_t s = 0; s < n; ++s) {
    if (label[s] >= 0) continue;
    const std::int32_t id = static_cast<std::int32_t>(rep_node.size());
    std::int64_t best = -1;  // a node with no cut edge around it, if any
    queue.clear();
    queue.push_back(s);
    label[s] = id;
    for (std::size_t qi = 0; qi < queue.size(); ++qi) {
      const std::int64_t p = queue[qi];
      const int i = static_cast<int>(p % nx), j = static_cast<int>((p / nx) % ny), k = static_cast<int>(p / sz);
      int open = 0;
      auto visit = [&](bool ok, std::int64_t q) {
        if (!ok) return;
        ++open;
        if (label[q] < 0) {
          label[q] = id;
          queue.push_back(q);
        }
      };
      visit(i + 1 < nx && !(cut[p] & 1), p + 1);
      visit(i > 0 && !(cut[p - 1] & 1), p - 1);
      visit(j + 1 < ny && !(cut[p] & 2), p + sy);
      visit(j > 0 && !(cut[p - sy] & 2), p - sy);
      visit(k + 1 < nz && !(cut[p] & 4), p + sz);
      visit(k > 0 && !(cut[p - sz] & 4), p - sz);
      const int neighbours = (i + 1 < nx) + (i > 0) + (j + 1 < ny) + (j > 0) + (k + 1 < nz) + (k > 0);
      if (best < 0 && open == neighbours) best = p;
    }
    rep_node.push_back(best >= 0 ? best : s);
  }
  const std::int64_t nc = static_cast<std::int64_t>(rep_node.size());
  MatrixX3d R(nc, 3);
  for (std::int64_t c = 0; c < nc; ++c) {
    const std::int64_t p = rep_node[c];
    R.row(c) << GridCoord(g, 0, static_cast<int>(p % nx)), GridCoord(g, 1, static_cast<int>((p / nx) % ny)),
        GridCoord(g, 2, static_cast<int>(p / sz));
  }
  const VectorXd wc = WindingNumbersExact(mesh, R);
  VectorXd w(n);
  for (std::int64_t p = 0; p < n; ++p) w[p] = Orient(wc[label[p]], abs);
  rep->components = nc;
  rep->exact_evaluations += nc;
  return w;
}

// The "sheet" faces of the auto open-mesh rule: faces whose two sides (at
// +-h/2 along the normal from the centroid) get the same threshold answer.
Mesh SheetFaces(const Mesh& mesh, double h, Sum sum, const VoxelizeOptions& o, bool abs, VoxelizeReport* rep) {
  const int nf = mesh.NumFaces();
  MatrixX3d S(2 * static_cast<std::int64_t>(nf), 3);
  for (int f = 0; f < nf; ++f) {
    const Vec3 a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)), c = mesh.V.row(mesh.F(f, 2));
    const Vec3 n = (b - a).cross(c - a).normalized();
    const Vec3 ce = (a + b + c) / 3.0;
    S.row(2 * f) = (ce + 0.5 * h * n).transpose();
    S.row(2 * f + 1) = (ce - 0.5 * h * n).transpose();
  }
  VectorXd ws;
  if (sum == Sum::kExact) {
    ws = WindingNumbersExact(mesh, S);
  } else {
    FastWindingNumber::Options fo;
    fo.beta = o.beta;
    ws = FastWindingNumber(mesh, fo).Eval(S);
  }
  std::vector<int> sheet;
  for (int f = 0; f < nf; ++f)
    if ((Orient(ws[2 * f], abs) > 0.5) == (Orient(ws[2 * f + 1], abs) > 0.5)) sheet.push_back(f);
  rep->sheet_faces = static_cast<std::int64_t>(sheet.size());
  Mesh sm;
  sm.V = mesh.V;
  sm.F.resize(static_cast<int>(sheet.size()), 3);
  for (std::size_t i = 0; i < sheet.size(); ++i) sm.F.row(static_cast<int>(i)) = mesh.F.row(sheet[i]);
  return sm;
}

// The auto open-mesh rule: nodes near "sheet" faces become occupied.
void AddSheetShell(const Mesh& mesh, const GridInfo& g, Sum sum, const VoxelizeOptions& o, bool abs, VectorXd* occ,
                   VoxelizeReport* rep) {
  double h = INFINITY;
  for (int a = 0; a < 3; ++a) h = std::min(h, (g.max[a] - g.min[a]) / (g.dims[a] - 1));
  const Mesh sm = SheetFaces(mesh, h, sum, o, abs, rep);
  if (sm.NumFaces() == 0) return;
  const double t = std::max(0.5 * o.epsilon, 0.87 * h);
  // Candidates: nodes in the sheet faces' boxes grown by t.
  std::vector<std::uint8_t> cand(g.NumNodes(), 0);
  for (int f = 0; f < sm.NumFaces(); ++f) {
    int lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      double mn = INFINITY, mx = -INFINITY;
      for (int c = 0; c < 3; ++c) mn = std::min(mn, sm.V(sm.F(f, c), a)), mx = std::max(mx, sm.V(sm.F(f, c), a));
      const double ha = (g.max[a] - g.min[a]) / (g.dims[a] - 1);
      lo[a] = ClampIndex(std::floor((mn - t - g.min[a]) / ha), 0, g.dims[a]);
      hi[a] = ClampIndex(std::ceil((mx + t - g.min[a]) / ha), -1, g.dims[a] - 1);
    }
    for (int k = lo[2]; k <= hi[2]; ++k)
      for (int j = lo[1]; j <= hi[1]; ++j)
        for (int i = lo[0]; i <= hi[0]; ++i) cand[NodeIndex(g, i, j, k)] = 1;
  }
  std::vector<std::int64_t> idx;
  for (std::int64_t p = 0; p < g.NumNodes(); ++p)
    if (cand[p] && (*occ)[p] == 0.0) idx.push_back(p);
  const TriangleBvh bvh(sm);
  std::vector<std::uint8_t> in(idx.size(), 0);
  const int nx = g.dims[0], ny = g.dims[1];
  ParallelFor(
      static_cast<std::int64_t>(idx.size()),
      [&](std::int64_t b, std::int64_t e) {
        for (std::int64_t r = b; r < e; ++r) {
          const std::int64_t p = idx[r];
          const Vec3 q(GridCoord(g, 0, static_cast<int>(p % nx)), GridCoord(g, 1, static_cast<int>((p / nx) % ny)),
                       GridCoord(g, 2, static_cast<int>(p / (static_cast<std::int64_t>(nx) * ny))));
          in[r] = bvh.Closest(q, t * t).face >= 0;
        }
      },
      256);
  for (std::size_t r = 0; r < idx.size(); ++r)
    if (in[r]) {
      (*occ)[idx[r]] = 1.0;
      ++rep->shell_nodes;
    }
}

}  // namespace

VolumeGrid Voxelize(const Mesh& mesh_in, const GridInfo& grid, const VoxelizeOptions& o, VoxelizeReport* report) {
  o.Check();
  if (grid.dim != 3 || grid.dims[0] < 2 || grid.dims[1] < 2 || grid.dims[2] < 2)
    throw OptionError("Voxelize needs a 3D grid with at least 2 nodes per axis");
  for (int a = 0; a < 3; ++a)
    if (!(std::isfinite(grid.min[a]) && std::isfinite(grid.max[a]) && grid.min[a] < grid.max[a]))
      throw OptionError("Voxelize: grid bounds must be finite with min < max");
  CheckMeshIndices(mesh_in, "Voxelize", /*finite=*/true);
  VoxelizeReport local;
  VoxelizeReport& rep = report ? *report : local;
  rep = VoxelizeReport{};
  Mesh mesh = DropDegenerateFaces(mesh_in, &rep.dropped_faces);
  if (o.open_mesh == "flip_dup") mesh = FlipDuplicate(mesh, o.epsilon);
  const bool abs = o.orientation == "abs";
  VolumeGrid out;
  out.info = grid;
  out.values = VectorXd::Zero(grid.NumNodes());
  rep.unbalanced_edges = CountUnbalancedEdges(mesh);
  rep.balanced = rep.unbalanced_edges == 0;
  if (mesh.NumFaces() == 0) {
    rep.path = "empty";
    return out;
  }
  VectorXd w;
  Sum sum = Sum::kExact;
  if (o.method == "ray_parity") {
    rep.path = "ray_parity";
    out.values = RayParityOccupancy(mesh, grid);
    rep.occupied = static_cast<std::int64_t>(out.values.sum());
    return out;
  } else if (o.method == "exact") {
    rep.path = "exact";
    w = SlabWinding(mesh, grid, Sum::kExact, o, abs, &rep.exact_evaluations);
    rep.exact_evaluations = grid.NumNodes();
  } else if (o.method == "naive") {
    rep.path = "naive";
    sum = Sum::kNaive;
    w = SlabWinding(mesh, grid, Sum::kNaive, o, abs, &rep.exact_evaluations);
  } else if (rep.balanced) {
    rep.path = "flood_fill";
    w = FloodWinding(mesh, grid, abs, &rep);
  } else {
    rep.path = "hierarchy";
    sum = Sum::kFast;
    w = SlabWinding(mesh, grid, Sum::kFast, o, abs, &rep.exact_evaluations);
  }
  VectorXd occ(w.size());
  for (std::int64_t p = 0; p < w.size(); ++p) occ[p] = w[p] > 0.5 ? 1.0 : 0.0;
  if (o.open_mesh == "auto" && !rep.balanced && sum != Sum::kNaive)
    AddSheetShell(mesh, grid, sum, o, abs, &occ, &rep);
  rep.occupied = static_cast<std::int64_t>(occ.sum());
  if (o.output == "occupancy") {
    out.values = std::move(occ);
  } else {
    // Winding output: w, with shell nodes raised to 1.
    for (std::int64_t p = 0; p < w.size(); ++p)
      if (occ[p] > 0.5 && w[p] <= 0.5) w[p] = 1.0;
    out.values = std::move(w);
  }
  return out;
}

std::vector<std::uint8_t> OccupancyAtPoints(const Mesh& mesh_in, const MatrixX3d& Q, double h,
                                            const VoxelizeOptions& o, VoxelizeReport* report) {
  o.Check();
  if (!(std::isfinite(h) && h > 0.0)) throw OptionError("OccupancyAtPoints: the shell spacing h must be finite and > 0");
  if (o.method == "ray_parity") throw OptionError("OccupancyAtPoints: method ray_parity works on grids only");
  CheckMeshIndices(mesh_in, "OccupancyAtPoints", /*finite=*/true);
  VoxelizeReport local;
  VoxelizeReport& rep = report ? *report : local;
  rep = VoxelizeReport{};
  Mesh mesh = DropDegenerateFaces(mesh_in, &rep.dropped_faces);
  if (o.open_mesh == "flip_dup") mesh = FlipDuplicate(mesh, o.epsilon);
  const bool abs = o.orientation == "abs";
  rep.unbalanced_edges = CountUnbalancedEdges(mesh);
  rep.balanced = rep.unbalanced_edges == 0;
  const std::int64_t n = Q.rows();
  std::vector<std::uint8_t> occ(static_cast<std::size_t>(n), 0);
  if (mesh.NumFaces() == 0 || n == 0) {
    rep.path = mesh.NumFaces() == 0 ? "empty" : "hierarchy";
    return occ;
  }
  // The grid path's sums without a grid: no flood fill (it needs grid
  // edges), so a balanced mesh takes the hierarchy + exact band too, whose
  // sign is exact away from the band (docs/voxelization.md).
  Sum sum = Sum::kFast;
  VectorXd w;
  if (o.method == "exact") {
    sum = Sum::kExact;
    rep.path = "exact";
    w = WindingNumbersExact(mesh, Q);
    rep.exact_evaluations = n;
  } else if (o.method == "naive") {
    sum = Sum::kNaive;
    rep.path = "naive";
    w = WindingNumbersNaive(mesh, Q);
  } else {
    rep.path = "hierarchy";
    FastWindingNumber::Options fo;
    fo.beta = o.beta;
    w = FastWindingNumber(mesh, fo).Eval(Q);
    if (o.exact_band > 0.0) {
      std::vector<std::int64_t> redo;
      for (std::int64_t r = 0; r < n; ++r)
        if (std::abs(Orient(w[r], abs) - 0.5) < o.exact_band) redo.push_back(r);
      if (!redo.empty()) {
        MatrixX3d R(static_cast<std::int64_t>(redo.size()), 3);
        for (std::size_t i = 0; i < redo.size(); ++i) R.row(static_cast<std::int64_t>(i)) = Q.row(redo[i]);
        const VectorXd we = WindingNumbersExact(mesh, R);
        for (std::size_t i = 0; i < redo.size(); ++i) w[redo[i]] = we[static_cast<std::int64_t>(i)];
        rep.exact_evaluations += static_cast<std::int64_t>(redo.size());
      }
    }
  }
  for (std::int64_t p = 0; p < n; ++p) occ[p] = Orient(w[p], abs) > 0.5 ? 1 : 0;
  if (o.open_mesh == "auto" && !rep.balanced && sum != Sum::kNaive) {
    const Mesh sm = SheetFaces(mesh, h, sum, o, abs, &rep);
    if (sm.NumFaces() > 0) {
      const double t = std::max(0.5 * o.epsilon, 0.87 * h);
      const TriangleBvh bvh(sm);
      std::vector<std::uint8_t> in(occ.size(), 0);
      ParallelFor(n, [&](std::int64_t b, std::int64_t e) {
        for (std::int64_t r = b; r < e; ++r)
          if (!occ[r]) in[r] = bvh.Closest(Q.row(r).transpose(), t * t).face >= 0;
      }, 256);
      for (std::int64_t r = 0; r < n; ++r)
        if (in[r]) occ[r] = 1, ++rep.shell_nodes;
    }
  }
  for (std::uint8_t v : occ) rep.occupied += v;
  return occ;
}

SignCheck VerifyOccupancy(const Mesh& mesh_in, const VolumeGrid& occ, const std::string& orientation, double margin,
                          std::int64_t random_nodes, std::uint64_t seed) {
  CheckMeshIndices(mesh_in, "VerifyOccupancy", /*finite=*/true);
  const GridInfo& g = occ.info;
  if (occ.values.size() != g.NumNodes()) throw Error("VerifyOccupancy: grid and values differ in size");
  const Mesh mesh = DropDegenerateFaces(mesh_in);
  const bool abs = orientation == "abs";
  SignCheck sc;
  sc.nodes = g.NumNodes();
  if (mesh.NumFaces() == 0) {
    for (std::int64_t p = 0; p < sc.nodes; ++p) sc.differences += occ.values[p] > 0.5;
    return sc;
  }
  const FastWindingNumber fwn(mesh);
  const std::int64_t slab = static_cast<std::int64_t>(g.dims[0]) * g.dims[1];
  std::vector<std::uint8_t> check(sc.nodes, 0);
  for (int k = 0; k < g.dims[2]; ++k) {
    const VectorXd wk = fwn.Eval(SlabNodes(g, k));
    for (std::int64_t r = 0; r < slab; ++r) {
      const double w = Orient(wk[r], abs);
      const bool fast_in = w > 0.5, in = occ.values[k * slab + r] > 0.5;
      if (fast_in != in) ++sc.fast_disagreements;
      if (fast_in != in || std::abs(w - 0.5) < margin) check[k * slab + r] = 1;
    }
  }
  Rng rng(seed);
  for (std::int64_t s = 0; s < random_nodes; ++s)
    check[static_cast<std::int64_t>(rng.NextU64() % static_cast<std::uint64_t>(sc.nodes))] = 1;
  std::vector<std::int64_t> idx;
  for (std::int64_t p = 0; p < sc.nodes; ++p)
    if (check[p]) idx.push_back(p);
  const int nx = g.dims[0], ny = g.dims[1];
  MatrixX3d Q(static_cast<std::int64_t>(idx.size()), 3);
  for (std::size_t r = 0; r < idx.size(); ++r) {
    const std::int64_t p = idx[r];
    Q.row(static_cast<std::int64_t>(r)) << GridCoord(g, 0, static_cast<int>(p % nx)),
        GridCoord(g, 1, static_cast<int>((p / nx) % ny)), GridCoord(g, 2, static_cast<int>(p / slab));
  }
  const VectorXd we = WindingNumbersExact(mesh, Q);
  sc.exact_checked = static_cast<std::int64_t>(idx.size());
  for (std::size_t r = 0; r < idx.size(); ++r)
    if ((Orient(we[static_cast<std::int64_t>(r)], abs) > 0.5) != (occ.values[idx[r]] > 0.5)) ++sc.differences;
  return sc;
}

}  // namespace arcs
