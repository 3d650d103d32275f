// Combinatorial topology: edges from sorted half-edge keys, components and
// vertex fans by union-find.
#include "framework/spatial/topology.h"

#include "framework/error.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <string>
#include <vector>

namespace arcs {
namespace {


class UnionFind {
 public:
  explicit UnionFind(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }
  int Find(int x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  }
  void Union(int a, int b) {
    a = Find(a), b = Find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<int> parent_;
};

}  // namespace

std::vector<int> FaceComponents(const Mesh& mesh, int* count) {
  const int nf = mesh.NumFaces();
  UnionFind verts(static_cast<std::size_t>(mesh.NumVertices()));
  for (int f = 0; f < nf; ++f) {
    verts.Union(mesh.F(f, 0), mesh.F(f, 1));
    verts.Union(mesh.F(f, 1), mesh.F(f, 2));
  }
  std::vector<int> root_comp(static_cast<std::size_t>(mesh.NumVertices()), -1), comp(nf);
  int nc = 0;
  for (int f = 0; f < nf; ++f) {
    const int r = verts.Find(mesh.F(f, 0));
    if (root_comp[r] < 0) root_comp[r] = nc++;
    comp[f] = root_comp[r];
  }
  if (count) *count = nc;
  return comp;
}

void CheckMeshIndices(const Mesh& mesh, const char* who, bool finite) {
  const int nv = mesh.NumVertices();
  for (int f = 0; f < mesh.NumFaces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.F(f, k);
      if (v < 0 || v >= nv)
        throw InputError("", 0, std::string(who) + ": face " + std::to_string(f) + " has vertex index " +
                                    std::to_string(v) + ", the mesh has " + std::to_string(nv) +
                                    " vertices");
      if (finite && !mesh.V.row(v).allFinite())
        throw InputError("", 0, std::string(who) + ": vertex " + std::to_string(v) + " (used by face " +
                                    std::to_string(f) + ") has a non-finite coordinate");
    }
  }
}

Topology ComputeTopology(const Mesh& mesh) {
  CheckMeshIndices(mesh, "ComputeTopology");
  Topology t;
  const int nv = mesh.NumVertices();
  const int nf = mesh.NumFaces();
  t.vertices = nv;
  t.faces = nf;

  // Area, signed volume (divergence theorem: sum a.(b x c) / 6) and degeneracy.
  for (int f = 0; f < nf; ++f) {
    const Vec3 a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)),
               c = mesh.V.row(mesh.F(f, 2));
    const Vec3 n = (b - a).cross(c - a);
    const double len = n.norm();
    t.area += 0.5 * len;
    t.volume += a.dot(b.cross(c)) / 6.0;
    const double e2 = std::max({(b - a).squaredNorm(), (c - a).squaredNorm(), (c - b).squaredNorm()});
    const bool repeated =
        mesh.F(f, 0) == mesh.F(f, 1) || mesh.F(f, 1) == mesh.F(f, 2) || mesh.F(f, 0) == mesh.F(f, 2);
    // Zero area up to rounding: |cross| below 1e-12 of the longest edge squared.
    if (repeated || len <= 1e-12 * e2) ++t.degenerate_faces;
  }

  // Half-edges (u -> v) of every face, keyed by the undirected edge.
  struct HalfEdge {
    std::int32_t lo, hi;  // undirected key, lo < hi
    std::int32_t face;
    std::int8_t corner;   // corner index of u in the face
    bool forward;         // u == lo
  };
  std::vector<HalfEdge> he;
  he.reserve(3 * static_cast<std::size_t>(nf));
  std::vector<char> referenced(nv, 0);
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int u = mesh.F(f, k), v = mesh.F(f, (k + 1) % 3);
      referenced[u] = 1;
      if (u == v) continue;  // collapsed edge of a degenerate face
      he.push_back({std::min(u, v), std::max(u, v), f, static_cast<std::int8_t>(k), u < v});
    }
  }
  t.referenced_vertices = static_cast<int>(std::count(referenced.begin(), referenced.end(), 1));
  std::sort(he.begin(), he.end(), [](const HalfEdge& a, const HalfEdge& b) {
    if (a.lo != b.lo) return a.lo < b.lo;
    if (a.hi != b.hi) return a.hi < b.hi;
    return a.face < b.face || (a.face == b.face && a.corner < b.corner);
  });

  // Corner union-find: corners 3f+k of one vertex are joined when their faces
  // share an edge through that vertex; each resulting class is one fan.
  UnionFind corners(3 * static_cast<std::size_t>(nf));
  UnionFind verts(nv);
  bool oriented = true;
  for (std::size_t i = 0; i < he.size();) {
    std::size_t j = i;
    while (j < he.size() && he[j].lo == he[i].lo && he[j].hi == he[i].hi) ++j;
    const int count = static_cast<int>(j - i);
    ++t.edges;
    if (count == 1) ++t.boundary_edges;
    if (count > 2) ++t.nonmanifold_edges;
    int fwd = 0, bwd = 0;
    for (std::size_t a = i; a < j; ++a) (he[a].forward ? fwd : bwd)++;
    if (fwd > 1 || bwd > 1) oriented = false;  // a directed edge used twice
    // Corner of vertex `x` in face f: the face's corner whose index is x.
    auto corner_of = [&](int f, int x) {
      for (int k = 0; k < 3; ++k)
        if (mesh.F(f, k) == x) return 3 * f + k;
      return 3 * f;
    };
    for (std::size_t a = i + 1; a < j; ++a) {
      corners.Union(corner_of(he[i].face, he[i].lo), corner_of(he[a].face, he[i].lo));
      corners.Union(corner_of(he[i].face, he[i].hi), corner_of(he[a].face, he[i].hi));
    }
    i = j;
  }
  for (int f = 0; f < nf; ++f) {
    // Components: a face joins its vertices (faces sharing only a vertex are
    // one component, as documented).
    verts.Union(mesh.F(f, 0), mesh.F(f, 1));
    verts.Union(mesh.F(f, 1), mesh.F(f, 2));
  }

  // Fans per vertex: distinct corner roots among the vertex's corners.
  {
    std::vector<std::pair<int, int>> vr;  // (vertex, corner root)
    vr.reserve(3 * static_cast<std::size_t>(nf));
    for (int f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k) vr.push_back({mesh.F(f, k), corners.Find(3 * f + k)});
    std::sort(vr.begin(), vr.end());
    vr.erase(std::unique(vr.begin(), vr.end()), vr.end());
    for (std::size_t i = 0; i < vr.size();) {
      std::size_t j = i;
      while (j < vr.size() && vr[j].first == vr[i].first) ++j;
      if (j - i > 1) ++t.nonmanifold_vertices;
      i = j;
    }
  }

  // Components and per-component Euler characteristic chi = V - E + F.
  std::vector<int> comp_id(nv, -1);
  int nc = 0;
  for (int v = 0; v < nv; ++v) {
    if (!referenced[v]) continue;
    const int r = verts.Find(v);
    if (comp_id[r] < 0) comp_id[r] = nc++;
  }
  t.components = nc;
  std::vector<long> chi(nc, 0);
  for (int v = 0; v < nv; ++v)
    if (referenced[v]) chi[comp_id[verts.Find(v)]] += 1;
  for (int f = 0; f < nf; ++f) chi[comp_id[verts.Find(mesh.F(f, 0))]] += 1;
  for (std::size_t i = 0; i < he.size();) {
    std::size_t j = i;
    while (j < he.size() && he[j].lo == he[i].lo && he[j].hi == he[i].hi) ++j;
    chi[comp_id[verts.Find(he[i].lo)]] -= 1;
    i = j;
  }

  t.euler = t.referenced_vertices - t.edges + t.faces;
  t.closed = nf > 0 && t.boundary_edges == 0;
  t.edge_manifold = t.nonmanifold_edges == 0;
  t.manifold = t.edge_manifold && t.nonmanifold_vertices == 0;
  t.oriented = oriented;
  if (t.closed && t.manifold && t.oriented) {
    long g2 = 0;
    bool ok = true;
    for (int c = 0; c < nc; ++c) {
      if ((2 - chi[c]) % 2 != 0 || chi[c] > 2) ok = false;
      g2 += (2 - chi[c]) / 2;
    }
    t.genus = ok ? static_cast<int>(g2) : -1;
  } else {
    t.genus = -1;
  }
  return t;
}

}  // namespace arcs
