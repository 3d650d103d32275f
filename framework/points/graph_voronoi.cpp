// Graph-Voronoi reconstruction: steps 2-5 of the paper, orientation,
// triangulation and the driver. Step 1 (the κNN graph) is in graph_knn.cpp.
// Everything after the κNN graph is combinatorial (no geometric predicate)
// except the signed volume that picks the outward side of a closed component
// and the diagonal lengths of the final triangulation.
#include "framework/points/graph_voronoi.h"
#include "framework/points/graph_internal.h"

#include "framework/error.h"
#include "framework/util/parallel.h"

#include <Eigen/Geometry>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <sstream>
#include <unordered_set>
#include <vector>

namespace arcs {
namespace {

using Clock = std::chrono::steady_clock;

// The fewest vertices of a closed triangulated surface (the tetrahedron). A
// CDM whose faces touch fewer sites is at most one triangle: it spans no
// surface, the subsample is too coarse for the cloud (adapt_k).
constexpr int kMinSurfaceSites = 4;
double Since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

std::uint64_t EdgeKey(int a, int b) {
  if (a > b) std::swap(a, b);
  return static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32 | static_cast<std::uint32_t>(b);
}

// CDM adjacency with edge ids; neighbours sorted (edges are sorted by (s, t),
// so filling in edge order lists smaller neighbours first, each run ascending).
struct CdmAdjacency {
  std::vector<int> off, nb, ed;
  explicit CdmAdjacency(const CombinatorialDelaunayMap& cdm) {
    const int ns = cdm.num_sites;
    off.assign(ns + 1, 0);
    for (const auto& e : cdm.edges) {
      ++off[e[0] + 1];
      ++off[e[1] + 1];
    }
    for (int i = 0; i < ns; ++i) off[i + 1] += off[i];
    nb.resize(off[ns]);
    ed.resize(off[ns]);
    std::vector<int> pos(off.begin(), off.end() - 1);
    for (int e = 0; e < static_cast<int>(cdm.edges.size()); ++e) {
      const int s = cdm.edges[e][0], t = cdm.edges[e][1];
      nb[pos[s]] = t;
      ed[pos[s]++] = e;
      nb[pos[t]] = s;
      ed[pos[t]++] = e;
    }
  }
};

// Depth-first search for the cycles of one length through one start edge.
// Canonical form (each cycle found once): u = its smallest vertex, v = the
// smaller of u's two cycle neighbours; the path u, v, ... returns to u from a
// vertex x > v, and every vertex is > u.
struct CycleSearch {
  const CdmAdjacency& adj;
  std::vector<std::uint8_t>& use;
  const std::vector<int>& dist;  // lower bound of the hop distance to u (stamped)
  const std::vector<int>& dist_stamp;
  std::vector<std::uint8_t>& on_path;
  std::vector<std::vector<int>>& faces;
  int u = 0, v = 0, L = 0, e0 = 0, stamp = 0;
  std::int64_t steps = 0, budget = 0;
  bool truncated = false;
  std::vector<int> path, path_edges;

  CycleSearch(const CdmAdjacency& a, std::vector<std::uint8_t>& u_, const std::vector<int>& d,
              const std::vector<int>& ds, std::vector<std::uint8_t>& op,
              std::vector<std::vector<int>>& f)
      : adj(a), use(u_), dist(d), dist_stamp(ds), on_path(op), faces(f) {}

  int Dist(int y) const { return dist_stamp[y] == stamp ? dist[y] : std::numeric_limits<int>::max(); }

  // Returns true to stop the whole search (start edge saturated or budget).
  bool Go(int x, int depth) {
    if (++steps > budget) {
      truncated = true;
      return true;
    }
    for (int i = adj.off[x]; i < adj.off[x + 1]; ++i) {
      const int y = adj.nb[i], ey = adj.ed[i];
      if (use[ey] >= 2) continue;
      if (y == u) {
        if (depth + 1 != L || ey == e0 || x <= v) continue;
        bool ok = true;
        for (int e : path_edges) ok = ok && use[e] < 2;
        if (!ok) continue;
        for (int e : path_edges) ++use[e];
        ++use[ey];
        faces.push_back(path);
        if (use[e0] >= 2) return true;
        continue;
      }
      if (y < u || on_path[y] || depth + 1 >= L) continue;
      if (Dist(y) > L - depth - 1) continue;
      on_path[y] = 1;
      path.push_back(y);
      path_edges.push_back(ey);
      const bool stop = Go(y, depth + 1);
      path.pop_back();
      path_edges.pop_back();
      on_path[y] = 0;
      if (stop) return true;
    }
    return false;
  }
};

}  // namespace

void GraphVoronoiOptions::Check() const {
  ARCS_CHECK_OPTION(kappa >= 1 && kappa <= 256, "kappa", kappa, "in [1, 256]");
  ARCS_CHECK_OPTION(k >= 1 && k <= 1000, "k", k, "in [1, 1000]");
  ARCS_CHECK_OPTION(a >= 0 && a <= 1000000, "a", a, "in [0, 1e6]");
  ARCS_CHECK_OPTION(max_face_size >= 3 && max_face_size <= 64, "max_face_size", max_face_size,
                    "in [3, 64]");
  ARCS_CHECK_OPTION(cycle_search_budget >= 1 && cycle_search_budget <= 1000000000, "cycle_search_budget",
                    cycle_search_budget, "in [1, 1e9]");
  ARCS_CHECK_OPTION(outlier_ratio == 0.0 || (outlier_ratio >= 1.0 && outlier_ratio <= 1e12), "outlier_ratio",
                    outlier_ratio, "0 (off) or in [1, 1e12]");
}

std::vector<int> GreedyKHopIndependentSet(const CsrGraph& g, int k,
                                          const std::vector<std::uint8_t>* skip,
                                          const std::vector<int>* priority) {
  const int n = g.NumNodes();
  std::vector<std::uint8_t> eligible(n, 1);
  if (skip)
    for (int v = 0; v < n; ++v)
      if ((*skip)[v]) eligible[v] = 0;
  std::vector<int> stamp(n, -1), queue;
  queue.reserve(4096);
  std::vector<int> sites;
  const int* adj = g.adj.data();
  for (int i = 0; i < n; ++i) {
    const int v = priority ? (*priority)[i] : i;
    if (!eligible[v]) continue;
    sites.push_back(v);
    eligible[v] = 0;
    // Every node less than k hops away becomes ineligible (BFS to depth k-1).
    queue.clear();
    queue.push_back(v);
    stamp[v] = v;
    std::size_t head = 0;
    for (int depth = 1; depth <= k - 1; ++depth) {
      const std::size_t end = queue.size();
      if (head == end) break;
      for (; head < end; ++head) {
        const int x = queue[head];
        for (std::int64_t e = g.offsets[x]; e < g.offsets[x + 1]; ++e) {
          const int w = adj[e];
          if (stamp[w] == v) continue;
          stamp[w] = v;
          eligible[w] = 0;
          queue.push_back(w);
        }
      }
    }
  }
  return sites;
}

std::vector<int> GraphVoronoiCells(const CsrGraph& g, const std::vector<int>& sites,
                                   std::vector<int>* hops) {
  const int n = g.NumNodes();
  std::vector<int> cell(n, -1), dist(n, -1);
  std::vector<int> frontier, next;
  frontier.reserve(sites.size());
  for (int i = 0; i < static_cast<int>(sites.size()); ++i) {
    const int s = sites[i];
    if (dist[s] == 0) continue;  // a repeated site keeps its first index
    dist[s] = 0;
    cell[s] = i;
    frontier.push_back(s);
  }
  // Level by level: a node first reached at level d+1 takes the smallest
  // label among its level-d neighbours = the smallest-index nearest site.
  for (int d = 0; !frontier.empty(); ++d) {
    next.clear();
    for (int x : frontier) {
      const int cx = cell[x];
      for (std::int64_t e = g.offsets[x]; e < g.offsets[x + 1]; ++e) {
        const int w = g.adj[e];
        if (dist[w] < 0) {
          dist[w] = d + 1;
          cell[w] = cx;
          next.push_back(w);
        } else if (dist[w] == d + 1 && cx < cell[w]) {
          cell[w] = cx;
        }
      }
    }
    frontier.swap(next);
  }
  if (hops) *hops = std::move(dist);
  return cell;
}

CombinatorialDelaunayMap BuildCombinatorialDelaunayMap(const CsrGraph& g,
                                                       const std::vector<int>& cell,
                                                       int num_sites, int a) {
  const int n = g.NumNodes();
  int max_deg = 0;
  for (int v = 0; v < n; ++v) max_deg = std::max(max_deg, g.Degree(v));
  // Distinct other cells among v's neighbours: v counts once in b(cell v, T)
  // for each such T. Both directions land on the same unordered key, so a
  // key's multiplicity is b(S,T) + b(T,S).
  auto distinct = [&](int v, int* buf) {
    const int c = cell[v];
    if (c < 0) return 0;
    int m = 0;
    for (std::int64_t e = g.offsets[v]; e < g.offsets[v + 1]; ++e) {
      const int cw = cell[g.adj[e]];
      if (cw < 0 || cw == c) continue;
      bool seen = false;
      for (int j = 0; j < m && !seen; ++j) seen = buf[j] == cw;
      if (!seen) buf[m++] = cw;
    }
    return m;
  };
  std::vector<std::int64_t> cnt(n + 1, 0);
  ParallelFor(n, [&](std::int64_t b, std::int64_t e) {
    std::vector<int> buf(max_deg + 1);
    for (std::int64_t v = b; v < e; ++v) cnt[v + 1] = distinct(static_cast<int>(v), buf.data());
  });
  for (int v = 0; v < n; ++v) cnt[v + 1] += cnt[v];
  std::vector<std::uint64_t> keys(cnt[n]);
  ParallelFor(n, [&](std::int64_t b, std::int64_t e) {
    std::vector<int> buf(max_deg + 1);
    for (std::int64_t v = b; v < e; ++v) {
      const int m = distinct(static_cast<int>(v), buf.data());
      for (int j = 0; j < m; ++j) keys[cnt[v] + j] = EdgeKey(cell[v], buf[j]);
    }
  });
  tbb::parallel_sort(keys.begin(), keys.end());
  CombinatorialDelaunayMap cdm;
  cdm.num_sites = num_sites;
  for (std::size_t i = 0; i < keys.size();) {
    std::size_t j = i;
    while (j < keys.size() && keys[j] == keys[i]) ++j;
    const std::int64_t count = static_cast<std::int64_t>(j - i);
    if (count > a) {
      cdm.edges.push_back({static_cast<int>(keys[i] >> 32), static_cast<int>(keys[i] & 0xffffffffu)});
      cdm.boundary.push_back(static_cast<int>(count));
    }
    i = j;
  }
  return cdm;
}

FaceEnumeration EnumerateFaces(const CombinatorialDelaunayMap& cdm, int max_face_size,
                               std::int64_t search_budget) {
  FaceEnumeration out;
  const int ns = cdm.num_sites;
  const int E = static_cast<int>(cdm.edges.size());
  const CdmAdjacency adj(cdm);
  std::vector<std::uint8_t>& use = out.edge_use;
  use.assign(E, 0);

  // Length 3: triangles (u, v, w), u < v < w, in lexicographic order.
  for (int e = 0; e < E; ++e) {
    const int u = cdm.edges[e][0], v = cdm.edges[e][1];
    int i = adj.off[u], j = adj.off[v];
    while (i < adj.off[u + 1] && adj.nb[i] <= v) ++i;
    while (j < adj.off[v + 1] && adj.nb[j] <= v) ++j;
    while (use[e] < 2 && i < adj.off[u + 1] && j < adj.off[v + 1]) {
      if (adj.nb[i] < adj.nb[j]) {
        ++i;
      } else if (adj.nb[i] > adj.nb[j]) {
        ++j;
      } else {
        const int w = adj.nb[i], e1 = adj.ed[i], e2 = adj.ed[j];
        if (use[e1] < 2 && use[e2] < 2) {
          ++use[e];
          ++use[e1];
          ++use[e2];
          out.faces.push_back({u, v, w});
        }
        ++i;
        ++j;
      }
    }
  }

  // Lengths 4 .. max_face_size over the edges still in fewer than two faces.
  std::vector<int> dist(ns, 0), dist_stamp(ns, -1), queue;
  std::vector<std::uint8_t> on_path(ns, 0);
  int stamp = 0;
  for (int L = 4; L <= max_face_size; ++L) {
    int bfs_root = -1;
    for (int e = 0; e < E; ++e) {
      if (use[e] >= 2) continue;
      const int u = cdm.edges[e][0], v = cdm.edges[e][1];
      if (u != bfs_root) {
        // Hop distances to u over available edges and vertices > u, up to
        // L - 2; later acceptances only lengthen them, so they stay lower
        // bounds for every start edge of u.
        bfs_root = u;
        ++stamp;
        queue.assign(1, u);
        dist_stamp[u] = stamp;
        dist[u] = 0;
        for (std::size_t h = 0; h < queue.size(); ++h) {
          const int x = queue[h];
          if (dist[x] >= L - 2) continue;
          for (int i = adj.off[x]; i < adj.off[x + 1]; ++i) {
            const int y = adj.nb[i];
            if (y <= u || use[adj.ed[i]] >= 2 || dist_stamp[y] == stamp) continue;
            dist_stamp[y] = stamp;
            dist[y] = dist[x] + 1;
            queue.push_back(y);
          }
        }
      }
      CycleSearch cs(adj, use, dist, dist_stamp, on_path, out.faces);
      cs.u = u;
      cs.v = v;
      cs.L = L;
      cs.e0 = e;
      cs.stamp = stamp;
      cs.budget = search_budget;
      cs.path = {u, v};
      cs.path_edges = {e};
      on_path[u] = on_path[v] = 1;
      cs.Go(v, 1);
      on_path[u] = on_path[v] = 0;
      if (cs.truncated) ++out.truncated_searches;
    }
  }
  return out;
}

GraphVoronoiResult ReconstructGraphVoronoi(const MatrixX3d& P, const GraphVoronoiOptions& opt) {
  opt.Check();
  const auto t_total = Clock::now();
  GraphVoronoiResult res;
  GraphVoronoiStats& st = res.stats;
  const std::int64_t n_in = P.rows();
  st.input_points = n_in;
  const char* who = "graph_voronoi";
  if (n_in < 4)
    throw InputError(who, 0, "needs at least 4 points, got " + std::to_string(n_in));
  if (n_in >= (std::int64_t{1} << 31) - 1)
    throw InputError(who, 0, "too many points (" + std::to_string(n_in) + ")");

  // --- Validation and duplicate merging.
  auto t = Clock::now();
  for (std::int64_t i = 0; i < n_in; ++i) {
    if (!std::isfinite(P(i, 0)) || !std::isfinite(P(i, 1)) || !std::isfinite(P(i, 2))) {
      std::ostringstream os;
      os << "point " << i << " (0-based) has a non-finite coordinate (" << P(i, 0) << ", "
         << P(i, 1) << ", " << P(i, 2) << ")";
      throw InputError(who, 0, os.str());
    }
  }
  if ((P.colwise().maxCoeff() - P.colwise().minCoeff()).maxCoeff() == 0.0) {
    std::ostringstream os;
    os << "all " << n_in << " points are at one position (" << P(0, 0) << ", " << P(0, 1) << ", "
       << P(0, 2) << ")";
    throw InputError(who, 0, os.str());
  }
  const int n = static_cast<int>(n_in);
  st.prep_s = Since(t);

  // --- Step 1: κNN graph (batched queries). Duplicates are detected by the
  // queries themselves (a neighbour at distance 0); only then are they merged
  // (sort by coordinates) and the queries repeated on the distinct points.
  t = Clock::now();
  std::vector<int> node_of_row;  // input row -> graph node (empty = identity)
  std::vector<int> row_of_node;  // graph node -> input row (first occurrence)
  MatrixX3d Qmerged;
  std::vector<double> mean_dist;
  std::vector<double>* md = opt.outlier_ratio > 0 ? &mean_dist : nullptr;
  bool coincident = false;
  double merge_s = 0;
  std::vector<int> order;  // graph node (Morton position) -> row of P (or of the merged points)
  std::vector<int> knn = KnnListsMorton(P, opt.kappa, &order, md, &st.kdtree_s,
                                        opt.merge_duplicates ? &coincident : nullptr);
  if (coincident) {
    const auto tm = Clock::now();
    std::vector<int> idx(n);
    std::iota(idx.begin(), idx.end(), 0);
    tbb::parallel_sort(idx.begin(), idx.end(), [&](int i, int j) {
      for (int d = 0; d < 3; ++d)
        if (P(i, d) != P(j, d)) return P(i, d) < P(j, d);
      return i < j;
    });
    std::vector<int> rep(n);  // input row -> first row with the same coordinates
    for (int s = 0; s < n;) {
      int e = s + 1;
      while (e < n && P(idx[e], 0) == P(idx[s], 0) && P(idx[e], 1) == P(idx[s], 1) &&
             P(idx[e], 2) == P(idx[s], 2))
        ++e;
      for (int r = s; r < e; ++r) rep[idx[r]] = idx[s];
      s = e;
    }
    node_of_row.resize(n);
    for (int i = 0; i < n; ++i) {
      if (rep[i] == i) {
        node_of_row[i] = static_cast<int>(row_of_node.size());
        row_of_node.push_back(i);
      } else {
        node_of_row[i] = node_of_row[rep[i]];  // rep[i] < i: already numbered
      }
    }
    const int m = static_cast<int>(row_of_node.size());
    if (m < 4)
      throw InputError(who, 0, "only " + std::to_string(m) + " distinct points among " +
                                   std::to_string(n) + ", needs at least 4");
    Qmerged.resize(m, 3);
    for (int v = 0; v < m; ++v) Qmerged.row(v) = P.row(row_of_node[v]);
    merge_s = Since(tm);
    st.prep_s += merge_s;
    knn = KnnListsMorton(Qmerged, opt.kappa, &order, md, &st.kdtree_s, nullptr);
  }
  const MatrixX3d& Q = coincident ? Qmerged : P;
  const int m = static_cast<int>(Q.rows());
  st.duplicates = n - m;
  std::vector<std::uint8_t> removed;
  if (opt.outlier_ratio > 0) {
    std::vector<double> tmp = mean_dist;
    std::nth_element(tmp.begin(), tmp.begin() + m / 2, tmp.end());
    const double limit = opt.outlier_ratio * tmp[m / 2];
    removed.assign(m, 0);
    for (int v = 0; v < m; ++v)
      if (mean_dist[v] > limit) {
        removed[v] = 1;
        ++st.outliers_removed;
      }
  }
  const std::vector<std::uint8_t>* rm = removed.empty() ? nullptr : &removed;
  const CsrGraph g = SymmetrizeKnn(knn, m, opt.kappa, rm);
  st.graph_edges = g.NumEdges();
  st.knn_s = Since(t) - merge_s;  // the merge counts as preparation

  // --- Steps 2-5 at the requested k; on a cloud too small for k (the faces
  // span fewer than kMinSurfaceSites sites: none, or one triangle) again with
  // k-1, ..., 2 when adapt_k is set (see the header). Times add up over the
  // attempts.
  std::vector<int> pos(m);  // row of Q -> graph node
  for (int v = 0; v < m; ++v) pos[order[v]] = v;
  std::vector<int> sites, cell;
  CombinatorialDelaunayMap cdm;
  FaceEnumeration fe;
  std::ostringstream tried;  // "k=5: 3 sites, 2 CDM edges; ..." for the error
  for (int k = opt.k;; --k) {
    // --- Step 2: maximal k-hop independent set.
    t = Clock::now();
    sites = GreedyKHopIndependentSet(g, k, rm, &pos);  // in row order
    st.sites = static_cast<int>(sites.size());
    st.mis_s += Since(t);

    // --- Step 3: graph Voronoi cells.
    t = Clock::now();
    cell = GraphVoronoiCells(g, sites);
    st.voronoi_s += Since(t);

    // --- Step 4: combinatorial Delaunay map.
    t = Clock::now();
    cdm = BuildCombinatorialDelaunayMap(g, cell, st.sites, opt.a);
    st.cdm_edges = static_cast<std::int64_t>(cdm.edges.size());
    {
      std::vector<std::uint8_t> has(st.sites, 0);
      for (const auto& e : cdm.edges) has[e[0]] = has[e[1]] = 1;
      st.cdm_vertices = static_cast<int>(std::count(has.begin(), has.end(), 1));
    }
    st.cdm_s += Since(t);

    // --- Step 5: faces as elementary cycles by increasing length.
    t = Clock::now();
    fe = EnumerateFaces(cdm, opt.max_face_size, opt.cycle_search_budget);
    st.cycles_s += Since(t);
    st.k_used = k;
    st.k_attempts.push_back(k);
    std::vector<std::uint8_t> in_face(st.sites, 0);
    for (const auto& f : fe.faces)
      for (int s : f) in_face[s] = 1;
    const int face_sites = static_cast<int>(std::count(in_face.begin(), in_face.end(), 1));
    if (face_sites >= kMinSurfaceSites) break;
    tried << (tried.tellp() > 0 ? "; " : "") << "k=" << k << ": " << st.sites << " sites, "
          << st.cdm_edges << " CDM edges, " << fe.faces.size() << " faces";
    if (!opt.adapt_k || k <= 2) {
      std::ostringstream os;
      os << "no surface: the faces of the combinatorial Delaunay map of the " << m
         << " points span fewer than " << kMinSurfaceSites << " sites (" << tried.str()
         << "; kappa=" << opt.kappa << ", a=" << opt.a << "): the cloud is too small or too sparse"
         << (opt.adapt_k ? "" : " at this k (adapt_k is off)");
      throw InputError(who, 0, os.str());
    }
  }
  t = Clock::now();
  st.truncated_searches = fe.truncated_searches;
  st.faces = static_cast<std::int64_t>(fe.faces.size());
  st.faces_by_size.assign(opt.max_face_size + 1, 0);
  for (const auto& f : fe.faces) ++st.faces_by_size[f.size()];
  st.triangles_before = st.faces_by_size[3];
  st.pct_triangles = st.faces > 0 ? 100.0 * st.triangles_before / st.faces : 0.0;
  st.genus_value = (2.0 - st.cdm_vertices + static_cast<double>(st.cdm_edges) - st.faces) / 2.0;
  for (std::uint8_t u : fe.edge_use) {
    if (u == 0) ++st.unused_edges;
    if (u == 1) ++st.boundary_edges;
  }
  st.cycles_s += Since(t);

  // Vertex positions: the sites, or the means of their cells.
  res.sites.resize(sites.size());
  for (std::size_t i = 0; i < sites.size(); ++i)
    res.sites[i] = coincident ? row_of_node[order[sites[i]]] : order[sites[i]];
  res.mesh.V.resize(st.sites, 3);
  if (opt.vertex_position == GraphVoronoiOptions::VertexPosition::kCellMean) {
    res.mesh.V.setZero();
    std::vector<int> count(st.sites, 0);
    for (int v = 0; v < m; ++v)
      if (cell[v] >= 0) {
        res.mesh.V.row(cell[v]) += Q.row(order[v]);
        ++count[cell[v]];
      }
    for (int s = 0; s < st.sites; ++s) res.mesh.V.row(s) /= std::max(count[s], 1);
  } else {
    for (int s = 0; s < st.sites; ++s) res.mesh.V.row(s) = Q.row(order[sites[s]]);
  }
  res.point_vertex.resize(n);
  for (int i = 0; i < n; ++i) res.point_vertex[i] = cell[pos[coincident ? node_of_row[i] : i]];

  // --- Orientation: propagate across edges shared by two faces; then each
  // component outward by its signed volume (exact for a closed component, a
  // heuristic for an open one, e.g. a surface with a few holes).
  t = Clock::now();
  std::vector<std::vector<int>>& polys = fe.faces;
  const int F = static_cast<int>(polys.size());
  {
    auto edge_id = [&](int x, int y) {
      const std::array<int, 2> key{std::min(x, y), std::max(x, y)};
      return static_cast<int>(std::lower_bound(cdm.edges.begin(), cdm.edges.end(), key) -
                              cdm.edges.begin());
    };
    const int E = static_cast<int>(cdm.edges.size());
    std::vector<int> inc_face(2 * static_cast<std::size_t>(E), -1);
    std::vector<std::uint8_t> inc_dir(2 * static_cast<std::size_t>(E), 0), inc_n(E, 0);
    std::vector<std::int64_t> foff(F + 1, 0);
    for (int f = 0; f < F; ++f) foff[f + 1] = foff[f] + static_cast<std::int64_t>(polys[f].size());
    std::vector<int> fedge(foff[F]);
    std::vector<std::uint8_t> fdir(foff[F]);
    for (int f = 0; f < F; ++f) {
      const auto& p = polys[f];
      for (std::size_t i = 0; i < p.size(); ++i) {
        const int x = p[i], y = p[(i + 1) % p.size()];
        const int e = edge_id(x, y);
        fedge[foff[f] + i] = e;
        fdir[foff[f] + i] = x < y;
        const int slot = inc_n[e]++;
        inc_face[2 * e + slot] = f;
        inc_dir[2 * e + slot] = x < y;
      }
    }
    std::vector<signed char> flip(F, -1);
    std::vector<int> comp(F, -1), queue;
    std::vector<std::uint8_t> comp_open;
    std::vector<double> comp_vol;
    const MatrixX3d& V = res.mesh.V;
    for (int f0 = 0; f0 < F; ++f0) {
      if (flip[f0] >= 0) continue;
      const int c = static_cast<int>(comp_open.size());
      comp_open.push_back(0);
      comp_vol.push_back(0.0);
      flip[f0] = 0;
      comp[f0] = c;
      queue.assign(1, f0);
      for (std::size_t h = 0; h < queue.size(); ++h) {
        const int f = queue[h];
        for (std::int64_t i = foff[f]; i < foff[f + 1]; ++i) {
          const int e = fedge[i];
          if (inc_n[e] < 2) {
            comp_open[c] = 1;
            continue;
          }
          const int slot = inc_face[2 * e] == f ? 1 : 0;
          const int g2 = inc_face[2 * e + slot];
          const int dg = inc_dir[2 * e + slot];
          const int df = fdir[i] ^ flip[f];
          const int want = dg ^ (1 - df);  // g2 must traverse e the other way
          if (flip[g2] < 0) {
            flip[g2] = static_cast<signed char>(want);
            comp[g2] = c;
            queue.push_back(g2);
          } else if (flip[g2] != want && g2 > f) {
            ++st.orientation_conflicts;
          }
        }
      }
    }
    for (int f = 0; f < F; ++f) {
      const auto& p = polys[f];
      double vol = 0;
      for (std::size_t i = 1; i + 1 < p.size(); ++i)
        vol += Vec3(V.row(p[0])).dot(Vec3(V.row(p[i])).cross(Vec3(V.row(p[i + 1]))));
      comp_vol[comp[f]] += flip[f] ? -vol : vol;
    }
    st.face_components = static_cast<int>(comp_open.size());
    for (std::size_t c = 0; c < comp_open.size(); ++c) st.closed_components += comp_open[c] ? 0 : 1;
    if (opt.orient) {
      for (int f = 0; f < F; ++f) {
        const int c = comp[f];
        const bool outward_flip = comp_vol[c] < 0;
        if (flip[f] ^ outward_flip) std::reverse(polys[f].begin(), polys[f].end());
      }
    }
  }
  st.orient_s = Since(t);

  // --- Triangulation of faces with more than three vertices: the
  // triangulation of the polygon (dynamic programme over its O(m^2)
  // diagonals) that first minimises the number of diagonals which already are
  // surface edges (each would put a third face on an edge), then the total
  // diagonal length. Faces are processed in order; their diagonals become
  // surface edges for the next ones.
  t = Clock::now();
  std::vector<std::array<int, 3>> tris;
  tris.reserve(2 * F);
  {
    std::unordered_set<std::uint64_t> edges;
    for (int e = 0; e < static_cast<int>(cdm.edges.size()); ++e)
      if (fe.edge_use[e] > 0) edges.insert(EdgeKey(cdm.edges[e][0], cdm.edges[e][1]));
    const MatrixX3d& V = res.mesh.V;
    struct Cost {
      int bad = 0;
      double len = 0;
      bool operator<(const Cost& o) const { return bad != o.bad ? bad < o.bad : len < o.len; }
      Cost operator+(const Cost& o) const { return {bad + o.bad, len + o.len}; }
    };
    std::vector<Cost> cost;
    std::vector<int> split;
    for (const auto& p : polys) {
      if (p.size() == 3) {
        tris.push_back({p[0], p[1], p[2]});
        continue;
      }
      if (!opt.triangulate) continue;
      const int r = static_cast<int>(p.size());
      // Chord (i, j) costs nothing when it is a polygon side.
      auto chord = [&](int i, int j) -> Cost {
        if (j == i + 1 || (i == 0 && j == r - 1)) return {};
        return {edges.count(EdgeKey(p[i], p[j])) ? 1 : 0, (V.row(p[i]) - V.row(p[j])).norm()};
      };
      cost.assign(static_cast<std::size_t>(r) * r, Cost{});
      split.assign(static_cast<std::size_t>(r) * r, -1);
      for (int len = 2; len < r; ++len)
        for (int i = 0; i + len < r; ++i) {
          const int j = i + len;
          Cost best{std::numeric_limits<int>::max(), 0};
          for (int m = i + 1; m < j; ++m) {
            const Cost c = cost[i * r + m] + cost[m * r + j] + chord(i, m) + chord(m, j);
            if (c < best) {
              best = c;
              split[i * r + j] = m;
            }
          }
          cost[i * r + j] = best;
        }
      st.forced_diagonals += cost[r - 1].bad;
      std::vector<std::array<int, 2>> stack{{0, r - 1}};
      while (!stack.empty()) {
        const auto [i, j] = stack.back();
        stack.pop_back();
        if (j - i < 2) continue;
        const int m = split[i * r + j];
        tris.push_back({p[i], p[m], p[j]});
        if (m - i > 1) edges.insert(EdgeKey(p[i], p[m]));
        if (j - m > 1) edges.insert(EdgeKey(p[m], p[j]));
        stack.push_back({i, m});
        stack.push_back({m, j});
      }
    }
  }
  res.mesh.F.resize(static_cast<Eigen::Index>(tris.size()), 3);
  for (std::size_t i = 0; i < tris.size(); ++i)
    for (int d = 0; d < 3; ++d) res.mesh.F(i, d) = tris[i][d];
  st.output_triangles = static_cast<std::int64_t>(tris.size());
  res.polygons = std::move(polys);
  st.triangulate_s = Since(t);
  st.total_s = Since(t_total);
  return res;
}

}  // namespace arcs
