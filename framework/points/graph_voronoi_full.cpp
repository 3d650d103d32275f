// Graph Voronoi at full resolution: see graph_voronoi_full.h.
#include "framework/points/graph_voronoi_full.h"

#include "framework/error.h"
#include "framework/points/delaunay_2d.h"
#include "framework/util/parallel.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <utility>

namespace arcs {

namespace {

constexpr int kTBits = 20;                       // edge parameters are k / 2^20
constexpr double kTScale = double(1 << kTBits);  // 2^20
constexpr double kShapeScale = 1024.0;           // face layout corners are multiples of 2^-10

std::uint64_t EdgeKey(int a, int b) {
  return (static_cast<std::uint64_t>(std::min(a, b)) << 32) | static_cast<std::uint32_t>(std::max(a, b));
}

// Closest point of triangle (a, b, c) to p (Ericson, Real-Time Collision
// Detection §5.1.5): barycentrics (exact zeros on the edge / vertex regions)
// and the squared distance.
double ClosestOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, double bary[3]) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  auto set = [&](double u, double v, double w) {
    bary[0] = u;
    bary[1] = v;
    bary[2] = w;
    return (p - (u * a + v * b + w * c)).squaredNorm();
  };
  if (d1 <= 0 && d2 <= 0) return set(1, 0, 0);
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return set(0, 1, 0);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    return set(1 - v, v, 0);
  }
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return set(0, 0, 1);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    return set(1 - w, 0, w);
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return set(0, 1 - w, w);
  }
  const double denom = va + vb + vc;
  if (!(std::abs(denom) > 0)) return set(1, 0, 0);  // degenerate triangle: its first corner
  const double v = vb / denom, w = vc / denom;
  return set(1 - v - w, v, w);
}

struct EdgePoint {
  std::int32_t k;    // parameter k / 2^20 from the smaller to the larger vertex id
  std::int32_t row;  // input row
};

// Delaunay edge flips on the surface (ours): an edge shared by exactly two
// triangles whose opposite angles sum to more than pi is replaced by the other
// diagonal of its quad, unless that diagonal already is an edge (which would
// make it non-manifold) or the two new triangles would fold against each
// other or against the old pair. Flips keep the vertices, the face count and
// the topology; they remove the slivers the per-face triangulation leaves
// along the coarse edges. At most max_flips flips (flips on a curved surface
// need not terminate by themselves). Returns the number of flips.
std::int64_t DelaunayFlips(const MatrixX3d& V, std::vector<std::array<int, 3>>* faces, std::int64_t max_flips) {
  auto& F = *faces;
  std::unordered_map<std::uint64_t, std::array<int, 3>> edge;  // key -> faces (two; [2] = count)
  edge.reserve(F.size() * 2);
  for (int f = 0; f < static_cast<int>(F.size()); ++f)
    for (int j = 0; j < 3; ++j) {
      auto& e = edge.try_emplace(EdgeKey(F[f][j], F[f][(j + 1) % 3]), std::array<int, 3>{-1, -1, 0}).first->second;
      if (e[2] < 2) e[e[2]] = f;
      ++e[2];
    }
  auto normal = [&](int a, int b, int c) -> Vec3 {
    return (V.row(b) - V.row(a)).transpose().cross((V.row(c) - V.row(a)).transpose());
  };
  auto angle = [&](int at, int x, int y) {
    const Vec3 p = (V.row(x) - V.row(at)).transpose(), q = (V.row(y) - V.row(at)).transpose();
    return std::atan2(p.cross(q).norm(), p.dot(q));
  };
  std::vector<std::uint64_t> work;
  work.reserve(edge.size());
  for (const auto& [k, e] : edge)
    if (e[2] == 2) work.push_back(k);
  std::sort(work.begin(), work.end());  // deterministic order
  std::int64_t flips = 0;
  while (!work.empty() && flips < max_flips) {
    const std::uint64_t key = work.back();
    work.pop_back();
    const auto it = edge.find(key);
    if (it == edge.end() || it->second[2] != 2) continue;
    const int f1 = it->second[0], f2 = it->second[1];
    const int x = static_cast<int>(key >> 32), y = static_cast<int>(key & 0xffffffffu);
    // Orient: f1 = (u, v, a) with u -> v, f2 = (v, u, b).
    int j1 = 0;
    while (j1 < 3 && !((F[f1][j1] == x || F[f1][j1] == y) && (F[f1][(j1 + 1) % 3] == x || F[f1][(j1 + 1) % 3] == y))) ++j1;
    if (j1 == 3) continue;
    const int u = F[f1][j1], v = F[f1][(j1 + 1) % 3], a = F[f1][(j1 + 2) % 3];
    int b = -1;
    for (int j = 0; j < 3; ++j)
      if (F[f2][j] == v && F[f2][(j + 1) % 3] == u) b = F[f2][(j + 2) % 3];
    if (b < 0 || a == b) continue;  // not consistently oriented here: leave it
    if (angle(a, u, v) + angle(b, v, u) <= M_PI + 1e-9) continue;
    if (edge.count(EdgeKey(a, b))) continue;
    const Vec3 n_old = normal(u, v, a).normalized() + normal(v, u, b).normalized();
    const Vec3 n1 = normal(a, u, b), n2 = normal(b, v, a);
    if (n1.dot(n2) <= 0 || n1.dot(n_old) <= 0 || n2.dot(n_old) <= 0) continue;
    F[f1] = {a, u, b};
    F[f2] = {b, v, a};
    edge.erase(it);
    edge[EdgeKey(a, b)] = {f1, f2, 2};
    auto replace = [&](int p, int q, int from, int to) {
      auto& e = edge[EdgeKey(p, q)];
      for (int j = 0; j < 2; ++j)
        if (e[j] == from) e[j] = to;
    };
    replace(u, b, f2, f1);
    replace(v, a, f1, f2);
    ++flips;
    for (const std::uint64_t k2 : {EdgeKey(a, u), EdgeKey(u, b), EdgeKey(b, v), EdgeKey(v, a)}) work.push_back(k2);
  }
  return flips;
}

}  // namespace

void FullResolutionOptions::Check() const {
  ARCS_CHECK_OPTION(interior_margin > 0 && interior_margin < 0.1, "interior_margin", interior_margin,
                    "in (0, 0.1)");
  ARCS_CHECK_OPTION(corner_margin > 0 && corner_margin < 0.5, "corner_margin", corner_margin, "in (0, 0.5)");
}

Mesh RefineGraphVoronoi(const MatrixX3d& P, const GraphVoronoiResult& coarse, const FullResolutionOptions& opt,
                        FullResolutionStats* stats_out) {
  opt.Check();
  const auto t0 = std::chrono::steady_clock::now();
  const char* who = "graph_voronoi full_resolution";
  const int n = static_cast<int>(P.rows());
  const Mesh& cm = coarse.mesh;
  const int nv = cm.NumVertices(), nf = cm.NumFaces();
  if (static_cast<int>(coarse.point_vertex.size()) != n || static_cast<int>(coarse.sites.size()) != nv)
    throw InputError(who, 0, "the coarse result does not belong to these points (" + std::to_string(n) +
                                 " points, " + std::to_string(coarse.point_vertex.size()) + " mapped)");
  for (int s = 0; s < nv; ++s)
    if (coarse.sites[s] < 0 || coarse.sites[s] >= n) throw InputError(who, 0, "site " + std::to_string(s) + " out of range");
  FullResolutionStats st;
  st.input_points = n;

  // Vertex -> incident faces (CSR).
  std::vector<int> off(nv + 1, 0), inc(3 * static_cast<std::size_t>(nf));
  for (int f = 0; f < nf; ++f)
    for (int j = 0; j < 3; ++j) ++off[cm.F(f, j) + 1];
  for (int v = 0; v < nv; ++v) off[v + 1] += off[v];
  {
    std::vector<int> fill(off.begin(), off.end() - 1);
    for (int f = 0; f < nf; ++f)
      for (int j = 0; j < 3; ++j) inc[fill[cm.F(f, j)]++] = f;
  }
  // Corners at the sites' own input points (so every vertex is an input point).
  auto corner = [&](int v) -> Vec3 { return P.row(coarse.sites[v]).transpose(); };

  // 1-2: assign every non-site row to a face (interior) or an edge.
  std::vector<std::uint8_t> is_site(n, 0);
  for (int s = 0; s < nv; ++s) is_site[coarse.sites[s]] = 1;
  std::vector<int> face_of(n, -1);              // interior points: their face
  std::vector<std::array<float, 2>> uv(n);      // interior points: barycentrics of corners 1, 2
  std::vector<std::uint64_t> edge_of(n, 0);     // edge points: edge key (0 = none)
  std::vector<std::int32_t> k_of(n, 0);
  std::vector<std::uint8_t> kind(n, 0);         // 0 dropped, 1 interior, 2 edge, 3 same position as its site
  ParallelFor(n, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t i = b; i < e; ++i) {
      const int v = coarse.point_vertex[i];
      if (is_site[i] || v < 0 || off[v] == off[v + 1]) continue;
      const Vec3 p = P.row(i).transpose();
      if (p == corner(v)) {
        kind[i] = 3;
        continue;
      }
      double best = std::numeric_limits<double>::infinity(), bb[3] = {1, 0, 0};
      int bf = -1;
      for (int x = off[v]; x < off[v + 1]; ++x) {
        const int f = inc[x];
        double bary[3];
        const double d = ClosestOnTriangle(p, corner(cm.F(f, 0)), corner(cm.F(f, 1)), corner(cm.F(f, 2)), bary);
        if (d < best) {
          best = d;
          bf = f;
          std::copy(bary, bary + 3, bb);
        }
      }
      const int zeros = (bb[0] == 0) + (bb[1] == 0) + (bb[2] == 0);
      if (zeros == 1) {
        const int z = bb[0] == 0 ? 0 : (bb[1] == 0 ? 1 : 2);
        const int a = cm.F(bf, (z + 1) % 3), c = cm.F(bf, (z + 2) % 3);  // edge a -> c, t = bary of c
        const double t = bb[(z + 2) % 3];
        if (t >= opt.corner_margin && t <= 1 - opt.corner_margin) {
          const double ts = a < c ? t : 1 - t;  // from the smaller vertex id
          std::int32_t k = static_cast<std::int32_t>(std::lround(ts * kTScale));
          k = std::clamp<std::int32_t>(k, 1, (1 << kTBits) - 1);
          edge_of[i] = EdgeKey(a, c);
          k_of[i] = k;
          kind[i] = 2;
          continue;
        }
      }
      // Interior (also points nearest a corner): clamp strictly inside.
      double u[3];
      double sum = 0;
      for (int j = 0; j < 3; ++j) sum += (u[j] = std::max(bb[j], opt.interior_margin));
      face_of[i] = bf;
      uv[i] = {static_cast<float>(u[1] / sum), static_cast<float>(u[2] / sum)};
      kind[i] = 1;
    }
  }, 4096);
  std::unordered_map<std::uint64_t, std::vector<EdgePoint>> edges;
  std::vector<std::vector<int>> face_pts(nf);
  for (int i = 0; i < n; ++i) {
    if (kind[i] == 1) {
      face_pts[face_of[i]].push_back(i);
      ++st.interior_points;
    } else if (kind[i] == 2) {
      edges[edge_of[i]].push_back({k_of[i], i});
      ++st.edge_points;
    } else if (kind[i] == 3) {
      ++st.merged_points;
    } else if (!is_site[i]) {
      ++st.dropped_points;
    }
  }
  for (auto& [key, list] : edges)
    std::sort(list.begin(), list.end(), [](const EdgePoint& x, const EdgePoint& y) {
      return x.k != y.k ? x.k < y.k : x.row < y.row;
    });

  // 3: per face, a Delaunay triangulation in its own plane.
  std::vector<std::vector<std::array<int, 3>>> out(nf);  // triangles in input rows
  std::vector<int> merged_in(nf, 0);
  ParallelFor(nf, [&](std::int64_t b, std::int64_t e) {
    std::vector<double> x, y;
    std::vector<int> rows;
    for (std::int64_t f = b; f < e; ++f) {
      const int c[3] = {cm.F(f, 0), cm.F(f, 1), cm.F(f, 2)};
      const Vec3 A = corner(c[0]), B = corner(c[1]), C = corner(c[2]);
      const Vec3 e1 = B - A, e2 = C - A;
      const double l2 = e1.squaredNorm();
      double cx = 0, cy = 1;  // a degenerate face is laid out as a right triangle
      if (l2 > 0) {
        cx = e1.dot(e2) / l2;
        cy = e1.cross(e2).norm() / l2;
        if (!std::isfinite(cx) || !std::isfinite(cy) || cy < 1.0 / 64) cx = 0, cy = std::max(cy, 1.0 / 64);
        cx = std::clamp(std::round(cx * kShapeScale) / kShapeScale, -64.0, 64.0);
        cy = std::clamp(std::round(cy * kShapeScale) / kShapeScale, 1.0 / 64, 64.0);
      }
      const double lx[3] = {0, 1, cx}, ly[3] = {0, 0, cy};
      x.assign(lx, lx + 3);
      y.assign(ly, ly + 3);
      rows.assign({coarse.sites[c[0]], coarse.sites[c[1]], coarse.sites[c[2]]});
      for (int j = 0; j < 3; ++j) {
        const int pa = c[j], pb = c[(j + 1) % 3];
        const auto it = edges.find(EdgeKey(pa, pb));
        if (it == edges.end()) continue;
        for (const EdgePoint& ep : it->second) {
          // t from pa to pb, exact (k / 2^20 or (2^20 - k) / 2^20); the
          // point pa + t (pb - pa) is exactly on the edge in these coordinates.
          const double t = (pa < pb ? ep.k : (1 << kTBits) - ep.k) / kTScale;
          const int ja = j, jb = (j + 1) % 3;
          x.push_back(lx[ja] + t * (lx[jb] - lx[ja]));
          y.push_back(ly[ja] + t * (ly[jb] - ly[ja]));
          rows.push_back(ep.row);
        }
      }
      for (int i : face_pts[f]) {
        const double u = uv[i][0], w = uv[i][1];
        x.push_back(u * lx[1] + w * lx[2]);
        y.push_back(u * ly[1] + w * ly[2]);
        rows.push_back(i);
      }
      int merged = 0;
      const auto tris = points_detail::Delaunay2D(x, y, &merged);
      merged_in[f] = merged;
      out[f].reserve(tris.size());
      for (const auto& t : tris) out[f].push_back({rows[t[0]], rows[t[1]], rows[t[2]]});
    }
  }, 16);

  // Assemble: vertices = the rows used, in row order.
  std::vector<int> vid(n, -1);
  std::int64_t ntri = 0;
  for (int f = 0; f < nf; ++f) {
    ntri += static_cast<std::int64_t>(out[f].size());
    for (const auto& t : out[f])
      for (int r : t) vid[r] = 0;
  }
  int nvert = 0;
  for (int i = 0; i < n; ++i)
    if (vid[i] == 0) vid[i] = nvert++;
  Mesh m;
  m.V.resize(nvert, 3);
  for (int i = 0; i < n; ++i)
    if (vid[i] >= 0) m.V.row(vid[i]) = P.row(i);
  std::vector<std::array<int, 3>> tri;
  std::vector<int> coarse_face;
  tri.reserve(ntri);
  coarse_face.reserve(ntri);
  for (int f = 0; f < nf; ++f)
    for (const auto& t : out[f]) {
      tri.push_back({vid[t[0]], vid[t[1]], vid[t[2]]});
      coarse_face.push_back(f);
    }
  if (opt.delaunay_flips) st.flips = DelaunayFlips(m.V, &tri, 20 * static_cast<std::int64_t>(tri.size()) + 100);
  m.F.resize(ntri, 3);
  for (std::int64_t r = 0; r < ntri; ++r) {
    const auto& t = tri[r];
    m.F.row(r) << t[0], t[1], t[2];
    const int f = coarse_face[r];  // the coarse face this slot came from (a flip keeps the slot)
    const Vec3 nc = (corner(cm.F(f, 1)) - corner(cm.F(f, 0))).cross(corner(cm.F(f, 2)) - corner(cm.F(f, 0)));
    const Vec3 nt = (m.V.row(t[1]) - m.V.row(t[0])).transpose().cross((m.V.row(t[2]) - m.V.row(t[0])).transpose());
    if (nt.dot(nc) < 0) ++st.folded_triangles;
  }
  // Rows that are neither vertices nor counted yet were merged in a face's plane.
  std::int64_t used_inserted = 0;
  for (int i = 0; i < n; ++i)
    if (vid[i] >= 0 && !is_site[i]) ++used_inserted;
  st.merged_points += st.interior_points + st.edge_points - used_inserted;
  st.vertices = nvert;
  st.pct_points = n > 0 ? 100.0 * nvert / n : 0;
  st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (stats_out) *stats_out = st;
  return m;
}

}  // namespace arcs
