// Botsch–Kobbelt patch remeshing on a small half-edge structure (see remesh.h).
#include "framework/rfts/remesh.h"

#include "framework/error.h"
#include "framework/spatial/topology.h"
#include "framework/spatial/triangle_bvh.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <unordered_map>

namespace arcs {

void RemeshOptions::Check() const {
  ARCS_CHECK_OPTION(target_edge_length > 0 && std::isfinite(target_edge_length), "target_edge_length",
                    target_edge_length, "a finite number > 0");
  ARCS_CHECK_OPTION(split_ratio > 1.0, "split_ratio", split_ratio, "> 1");
  ARCS_CHECK_OPTION(collapse_ratio > 0 && collapse_ratio < split_ratio, "collapse_ratio", collapse_ratio,
                    "in (0, split_ratio)");
  ARCS_CHECK_OPTION(iterations >= 0, "iterations", iterations, ">= 0");
}

namespace {

// Face f owns half-edges 3f, 3f+1, 3f+2; half-edge 3f+k runs from corner k to
// corner k+1 of the face, so next/prev are implicit.
inline int Next(int h) { return h - h % 3 + (h % 3 + 1) % 3; }
inline int Prev(int h) { return h - h % 3 + (h % 3 + 2) % 3; }

class HalfEdgeMesh {
 public:
  std::vector<Vec3> pos;
  std::vector<int> vhe;      // an outgoing half-edge per vertex (-1 = deleted)
  std::vector<int> to;       // target vertex of each half-edge
  std::vector<int> opp;      // twin half-edge
  std::vector<char> alive;   // per face
  std::vector<char> active;  // per face: inside the patch
  int num_vertices = 0;      // alive vertices

  explicit HalfEdgeMesh(const Mesh& m, const std::vector<char>& act) {
    const int nv = m.NumVertices(), nf = m.NumFaces();
    pos.resize(nv);
    for (int v = 0; v < nv; ++v) pos[v] = m.V.row(v).transpose();
    to.resize(3 * nf);
    opp.assign(3 * nf, -1);
    alive.assign(nf, 1);
    active.assign(nf, 1);
    if (!act.empty()) {
      if (static_cast<int>(act.size()) != nf)
        throw InputError("", 0, "RemeshPatch: " + std::to_string(act.size()) + " active flags for " +
                                    std::to_string(nf) + " faces");
      active = act;
    }
    vhe.assign(nv, -1);
    std::unordered_map<std::uint64_t, int> edge;
    edge.reserve(3 * nf);
    auto key = [](int a, int b) { return (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint32_t>(b); };
    for (int f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k) {
        const int a = m.F(f, k), b = m.F(f, (k + 1) % 3);
        to[3 * f + k] = b;
        vhe[a] = 3 * f + k;
        if (!edge.emplace(key(a, b), 3 * f + k).second)
          throw InputError("", 0, "RemeshPatch: edge (" + std::to_string(a) + ", " + std::to_string(b) +
                                      ") is used twice in one direction (not an oriented manifold)");
      }
    num_vertices = static_cast<int>(std::count_if(vhe.begin(), vhe.end(), [](int h) { return h >= 0; }));
    for (int h = 0; h < 3 * nf; ++h) {
      auto it = edge.find(key(to[h], From(h)));
      if (it == edge.end())
        throw InputError("", 0, "RemeshPatch: the mesh is not closed (edge " + std::to_string(From(h)) + "-" +
                                    std::to_string(to[h]) + " has one face)");
      opp[h] = it->second;
    }
  }

  int From(int h) const { return to[Prev(h)]; }
  int NumFaces() const { return static_cast<int>(alive.size()); }
  Vec3 Normal(int f) const {  // unnormalised (2·area)
    const Vec3& a = pos[to[3 * f + 2]];
    return (pos[to[3 * f]] - a).cross(pos[to[3 * f + 1]] - a);
  }
  double Length(int h) const { return (pos[to[h]] - pos[From(h)]).norm(); }

  // Outgoing half-edges of v, in rotation order.
  template <class Fn>
  void ForOutgoing(int v, Fn fn) const {
    const int start = vhe[v];
    int h = start;
    int guard = 0;
    do {
      fn(h);
      h = opp[Prev(h)];
      if (++guard > 100000) throw Error("RemeshPatch: corrupt vertex fan (internal error)");
    } while (h != start);
  }
  int Valence(int v) const {
    int n = 0;
    ForOutgoing(v, [&](int) { ++n; });
    return n;
  }
  bool Free(int v) const {
    bool free = true;
    ForOutgoing(v, [&](int h) { free = free && active[h / 3]; });
    return free;
  }
  std::vector<int> Neighbours(int v) const {
    std::vector<int> n;
    ForOutgoing(v, [&](int h) { n.push_back(to[h]); });
    return n;
  }

  // Rewrites faces `faces` (corner triples `tri`), deletes `dead` faces, and
  // relinks twins and vertex half-edges locally. The twins of the rewritten
  // faces are found among themselves and the faces' former outside twins.
  void Rewrite(const std::vector<int>& faces, const std::vector<std::array<int, 3>>& tri,
               const std::vector<int>& dead) {
    std::vector<int> outside;
    auto collect = [&](int f) {
      for (int k = 0; k < 3; ++k) {
        const int t = opp[3 * f + k];
        if (t < 0) continue;
        const int g = t / 3;
        if (std::find(faces.begin(), faces.end(), g) == faces.end() &&
            std::find(dead.begin(), dead.end(), g) == dead.end())
          outside.push_back(t);
      }
    };
    for (int f : faces) collect(f);
    for (int f : dead) collect(f);
    std::sort(outside.begin(), outside.end());
    outside.erase(std::unique(outside.begin(), outside.end()), outside.end());
    for (int f : dead) {
      alive[f] = 0;
      for (int k = 0; k < 3; ++k) opp[3 * f + k] = -1;
    }
    for (std::size_t i = 0; i < faces.size(); ++i)
      for (int k = 0; k < 3; ++k) to[3 * faces[i] + k] = tri[i][(k + 1) % 3];
    std::vector<int> hs = outside;
    for (int f : faces)
      for (int k = 0; k < 3; ++k) hs.push_back(3 * f + k);
    for (int h : hs) {
      int twin = -1;
      for (int g : hs)
        if (to[g] == From(h) && From(g) == to[h]) {
          if (twin >= 0) throw Error("RemeshPatch: operation made a non-manifold edge (internal error)");
          twin = g;
        }
      if (twin < 0) throw Error("RemeshPatch: operation opened the mesh (internal error)");
      opp[h] = twin;
    }
    for (int h : hs) vhe[From(h)] = h;
  }

  int AddFace(char act) {
    alive.push_back(1);
    active.push_back(act);
    to.insert(to.end(), {0, 0, 0});
    opp.insert(opp.end(), {-1, -1, -1});
    return NumFaces() - 1;
  }

  // h: a -> b in face (a, b, c); its twin in (b, a, d).
  void Split(int h) {
    const int g = opp[h];
    const int f1 = h / 3, f2 = g / 3;
    const int a = From(h), b = to[h], c = to[Next(h)], d = to[Next(g)];
    const int m = static_cast<int>(pos.size());
    pos.push_back(0.5 * (pos[a] + pos[b]));
    vhe.push_back(-1);
    ++num_vertices;
    const int f3 = AddFace(active[f1]), f4 = AddFace(active[f2]);
    Rewrite({f1, f3, f2, f4}, {{{a, m, c}}, {{m, b, c}}, {{b, m, d}}, {{m, a, d}}}, {});
  }

  // Edge a -> b in (a, b, c), twin in (b, a, d) becomes c - d.
  void Flip(int h) {
    const int g = opp[h];
    const int a = From(h), b = to[h], c = to[Next(h)], d = to[Next(g)];
    Rewrite({h / 3, g / 3}, {{{a, d, c}}, {{b, c, d}}}, {});
  }

  // Collapses a -> b into b, placed at `p`.
  void Collapse(int h, const Vec3& p) {
    const int g = opp[h];
    const int a = From(h), b = to[h];
    std::vector<int> faces;
    std::vector<std::array<int, 3>> tri;
    ForOutgoing(a, [&](int e) {
      const int f = e / 3;
      if (f == h / 3 || f == g / 3) return;
      std::array<int, 3> t{to[3 * f + 2], to[3 * f], to[3 * f + 1]};
      for (int& x : t)
        if (x == a) x = b;
      faces.push_back(f);
      tri.push_back(t);
    });
    pos[b] = p;
    Rewrite(faces, tri, {h / 3, g / 3});
    vhe[a] = -1;
    --num_vertices;
  }
};

double Deviation(int valence) { return std::abs(valence - 6); }

// Smallest 2·area / (longest edge)² of a face an operation may create (about
// the sine of its smallest angle): rejects slivers and zero-area faces.
constexpr double kMinShape = 1e-4;

}  // namespace

RemeshStats RemeshPatch(Mesh* mesh, const std::vector<char>& active_faces, const RemeshOptions& o) {
  o.Check();
  CheckMeshIndices(*mesh, "RemeshPatch", true);
  RemeshStats st;
  if (o.iterations == 0 || mesh->NumFaces() == 0) return st;
  HalfEdgeMesh m(*mesh, active_faces);
  const TriangleBvh* bvh = nullptr;
  std::unique_ptr<TriangleBvh> reference;
  if (o.project) {
    // Free vertices lie on active faces and stay near them: the patch alone
    // is the projection target (cheaper than the whole mesh for small patches).
    Mesh patch;
    patch.V = mesh->V;
    if (active_faces.empty()) {
      patch.F = mesh->F;
    } else {
      patch.F.resize(std::count_if(active_faces.begin(), active_faces.end(), [](char c) { return c != 0; }), 3);
      int r = 0;
      for (int f = 0; f < mesh->NumFaces(); ++f)
        if (active_faces[f]) patch.F.row(r++) = mesh->F.row(f);
    }
    if (patch.NumFaces() > 0) {
      reference = std::make_unique<TriangleBvh>(patch);
      bvh = reference.get();
    }
  }
  const double hi = o.split_ratio * o.target_edge_length;
  const double lo = o.collapse_ratio * o.target_edge_length;

  for (int it = 0; it < o.iterations; ++it) {
    // (1) Splits: every edge of the patch longer than hi, in index order.
    const int nh = static_cast<int>(m.to.size());
    for (int h = 0; h < nh; ++h) {
      if (!m.alive[h / 3] || h > m.opp[h]) continue;
      if (!m.active[h / 3] || !m.active[m.opp[h] / 3]) continue;
      if (m.Length(h) > hi) {
        m.Split(h);
        ++st.splits;
      }
    }
    // (2) Collapses of short edges between free vertices.
    for (int h = 0; h < static_cast<int>(m.to.size()); ++h) {
      if (!m.alive[h / 3] || h > m.opp[h]) continue;
      if (m.Length(h) >= lo) continue;
      const int a = m.From(h), b = m.to[h];
      if (!m.Free(a) || !m.Free(b)) continue;
      // Link condition: the one-rings of a and b share exactly the two
      // opposite vertices (keeps the mesh a manifold of the same genus).
      std::vector<int> na = m.Neighbours(a), nb = m.Neighbours(b);
      if (m.num_vertices <= 4) break;  // a tetrahedron has no collapsible edge
      int shared = 0;
      for (int x : na) shared += std::count(nb.begin(), nb.end(), x);
      if (shared != 2) continue;
      const Vec3 p = 0.5 * (m.pos[a] + m.pos[b]);
      bool ok = true;
      for (int x : na)
        if (x != b && (m.pos[x] - p).norm() > hi) ok = false;
      for (int x : nb)
        if (x != a && (m.pos[x] - p).norm() > hi) ok = false;
      if (!ok) continue;
      // No face around a or b may flip (or degenerate) when a, b move to p.
      const int f1 = h / 3, f2 = m.opp[h] / 3;
      auto check_fan = [&](int v) {
        m.ForOutgoing(v, [&](int e) {
          const int f = e / 3;
          if (f == f1 || f == f2 || !ok) return;
          const Vec3 n0 = m.Normal(f);
          Vec3 q[3];
          for (int k = 0; k < 3; ++k) {
            const int x = m.to[3 * f + (k + 2) % 3];
            q[k] = (x == a || x == b) ? p : m.pos[x];
          }
          const Vec3 n1 = (q[1] - q[0]).cross(q[2] - q[0]);
          if (n0.dot(n1) <= 0.0 || n1.norm() < kMinShape * hi * hi) ok = false;
        });
      };
      check_fan(a);
      check_fan(b);
      if (!ok) continue;
      m.Collapse(h, p);
      ++st.collapses;
    }
    // (3) Flips toward valence 6.
    for (int h = 0; h < static_cast<int>(m.to.size()); ++h) {
      if (!m.alive[h / 3] || h > m.opp[h]) continue;
      const int g = m.opp[h];
      if (!m.active[h / 3] || !m.active[g / 3]) continue;
      const int a = m.From(h), b = m.to[h], c = m.to[Next(h)], d = m.to[Next(g)];
      if (c == d) continue;
      const int va = m.Valence(a), vb = m.Valence(b), vc = m.Valence(c), vd = m.Valence(d);
      if (va <= 3 || vb <= 3) continue;
      const double before = Deviation(va) + Deviation(vb) + Deviation(vc) + Deviation(vd);
      const double after = Deviation(va - 1) + Deviation(vb - 1) + Deviation(vc + 1) + Deviation(vd + 1);
      if (after >= before) continue;
      std::vector<int> nc = m.Neighbours(c);
      if (std::find(nc.begin(), nc.end(), d) != nc.end()) continue;  // c-d already an edge
      // The two new faces must keep the orientation of the old pair.
      const Vec3 n0 = m.Normal(h / 3) + m.Normal(g / 3);
      const Vec3 n1 = (m.pos[d] - m.pos[a]).cross(m.pos[c] - m.pos[a]);
      const Vec3 n2 = (m.pos[c] - m.pos[b]).cross(m.pos[d] - m.pos[b]);
      if (n0.dot(n1) <= 0 || n0.dot(n2) <= 0) continue;
      const double l2 = std::max({(m.pos[a] - m.pos[b]).squaredNorm(), (m.pos[c] - m.pos[d]).squaredNorm(),
                                  (m.pos[a] - m.pos[c]).squaredNorm(), (m.pos[a] - m.pos[d]).squaredNorm(),
                                  (m.pos[b] - m.pos[c]).squaredNorm(), (m.pos[b] - m.pos[d]).squaredNorm()});
      if (n1.norm() < kMinShape * l2 || n2.norm() < kMinShape * l2) continue;  // would make a sliver
      m.Flip(h);
      ++st.flips;
    }
    // (4) Tangential relaxation of free vertices (Jacobi), (5) projection.
    const int nv = static_cast<int>(m.pos.size());
    std::vector<Vec3> moved(nv);
    std::vector<char> is_free(nv, 0);
    for (int v = 0; v < nv; ++v) {
      if (m.vhe[v] < 0 || !m.Free(v)) continue;
      Vec3 q = Vec3::Zero(), n = Vec3::Zero();
      int k = 0;
      m.ForOutgoing(v, [&](int e) {
        q += m.pos[m.to[e]];
        n += m.Normal(e / 3);
        ++k;
      });
      q /= k;
      const double nn = n.norm();
      if (nn > 0) n /= nn;
      moved[v] = q + n * n.dot(m.pos[v] - q);
      is_free[v] = 1;
    }
    // A vertex keeps its place when its move (relaxed and projected) would
    // flip or flatten one of its faces (vertices in index order).
    for (int v = 0; v < nv; ++v) {
      if (!is_free[v]) continue;
      const Vec3 target = bvh ? bvh->Closest(moved[v]).point : moved[v];
      const Vec3 old_pos = m.pos[v];
      std::vector<Vec3> before;
      m.ForOutgoing(v, [&](int e) { before.push_back(m.Normal(e / 3)); });
      m.pos[v] = target;
      bool ok = true;
      int k = 0;
      m.ForOutgoing(v, [&](int e) {
        const Vec3 n = m.Normal(e / 3);
        const double l2 = std::max({m.Length(3 * (e / 3)), m.Length(3 * (e / 3) + 1), m.Length(3 * (e / 3) + 2)});
        if (n.dot(before[k++]) <= 0 || n.norm() < kMinShape * l2 * l2) ok = false;
      });
      if (ok) ++st.relaxed;
      else m.pos[v] = old_pos;
    }
  }

  // Compact: drop deleted faces and vertices, keep the relative order.
  std::vector<int> remap(m.pos.size(), -1);
  int nv = 0;
  for (std::size_t v = 0; v < m.pos.size(); ++v)
    if (m.vhe[v] >= 0) remap[v] = nv++;
  int nf = 0;
  for (int f = 0; f < m.NumFaces(); ++f) nf += m.alive[f];
  mesh->V.resize(nv, 3);
  for (std::size_t v = 0; v < m.pos.size(); ++v)
    if (remap[v] >= 0) mesh->V.row(remap[v]) = m.pos[v].transpose();
  mesh->F.resize(nf, 3);
  int r = 0;
  for (int f = 0; f < m.NumFaces(); ++f) {
    if (!m.alive[f]) continue;
    for (int k = 0; k < 3; ++k) mesh->F(r, k) = remap[m.to[3 * f + (k + 2) % 3]];
    ++r;
  }
  return st;
}

}  // namespace arcs
