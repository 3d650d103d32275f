// Graph-Voronoi surface reconstruction from an unoriented point cloud
// (Dumitriu, Funke, Kutz, Milosavljević, "How much geometry it takes to
// reconstruct a 2-manifold in R^3"; paper in ../shared/papers/
// graph_voronoi_reconstruction.txt). The paper's five steps (§2, §3.1):
//
//  1. neighbourhood graph G(V): every point joined to its κ nearest neighbours
//     and the edges made undirected (i ~ j iff j ∈ kNN(i) or i ∈ kNN(j));
//  2. S = a maximal k-hop independent set of G (no two sites closer than k
//     hops), greedy: nodes in id order, a still-eligible node joins S and every
//     node less than k hops from it becomes ineligible;
//  3. graph Voronoi cells: every node goes to its hop-nearest site, ties to the
//     site with the smaller node id (level-synchronous multi-source BFS);
//  4. combinatorial Delaunay map CDM(S): sites s1, s2 adjacent iff
//     b(S1,S2) + b(S2,S1) > a, where b(S1,S2) = number of nodes of cell S1 with
//     at least one graph neighbour in cell S2;
//  5. faces = elementary cycles of CDM(S) enumerated by increasing length
//     (3, 4, ..., max_face_size); a cycle is accepted only while each of its
//     edges is in fewer than two accepted faces.
// Then (ours): faces are oriented consistently by propagation across shared
// edges (each component outward by its signed volume: exact when closed, a
// heuristic when open), and faces with more than three vertices are
// triangulated (the triangulation with fewest diagonals that already are
// surface edges, then shortest total diagonal length; dynamic programme).
//
// Node ids are the input row order (after merging duplicates, the first
// occurrence keeps its place); every tie is broken by id, so the output is
// deterministic and independent of the thread count. (Internally the graph is
// stored in Morton order for memory locality; the greedy order and the tie
// rule still follow the input ids, so the result is the same.)
//
// Points not chosen as sites are NOT vertices of the output: the mesh
// vertices are the sites (a subsample of the input), placed at the site's
// input point (vertex_position = kSite, the paper) or at the mean of its
// Voronoi cell (kCellMean). `point_vertex` maps every input point to the
// vertex of its cell, which is how a caller can refine or project.
//
// Degenerate input (documented, tested):
//  * fewer than 4 points, a non-finite coordinate, or all points at one
//    position -> InputError naming the problem (and the first bad row);
//  * duplicate points (bit-identical coordinates) are merged before the graph
//    is built (counted in stats.duplicates); they map to the same vertex;
//  * outliers: by default (the paper) they stay in the graph. A far outlier's
//    κ edges reach the surface points nearest to it, so it either joins a
//    cell or, as a site, adds a small "tent" to the surface. With
//    outlier_ratio > 0 a point whose mean distance to its κ neighbours is more
//    than outlier_ratio × the median of that quantity is removed first
//    (stats.outliers_removed; point_vertex = -1);
//  * an open or non-manifold result is returned as it is and described in
//    the stats (edges in no face, edges in one face, orientation conflicts);
//  * a cloud too small for k: with k = 5 a site's cell holds about 85 points
//    of a dense surface sample (the bunny: 35 947 points, 422 sites), so a
//    cloud of a few hundred points gets 2-7 sites, and their CDM has no cycle
//    (a path, a single edge: too few cells touch by more than a points) or
//    one triangle. A closed surface needs at least 4 vertices (tetrahedron),
//    so while the faces use fewer than 4 sites, adapt_k (default on) reruns
//    steps 2-5 with k-1, ..., 2 (the first k that spans 4 sites is kept,
//    stats.k_used / k_attempts); if even k = 2 does not (e.g. 10 points,
//    all within one hop of each other) -> InputError naming the point count
//    and the sites, CDM edges and faces of every k tried. An empty mesh is
//    never returned.
#pragma once

#include "framework/types.h"
#include "framework/util/enum_names.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace arcs {

// An undirected graph in compressed-row form; neighbours sorted by id.
struct CsrGraph {
  std::vector<std::int64_t> offsets;  // n + 1 entries
  std::vector<int> adj;               // both directions of every edge
  int NumNodes() const { return offsets.empty() ? 0 : static_cast<int>(offsets.size()) - 1; }
  int Degree(int v) const { return static_cast<int>(offsets[v + 1] - offsets[v]); }
  std::int64_t NumEdges() const { return static_cast<std::int64_t>(adj.size()) / 2; }
};

// Step 1: κ-nearest-neighbour graph of the rows of P, symmetrised. Queries
// are batched (kd-tree over Morton-ordered points, queries in Morton order,
// in parallel). Coincident points are neighbours at distance 0. If
// `mean_dist` is given it receives each point's mean distance to its κ
// neighbours. Nodes with `removed[v]` set get no edges (may be null).
CsrGraph BuildKnnGraph(const MatrixX3d& P, int kappa, std::vector<double>* mean_dist = nullptr,
                       const std::vector<std::uint8_t>* removed = nullptr);

// The directed κNN lists alone: n × kappa input ids (row v: v's neighbours,
// nearest first, itself excluded; -1 pads when n - 1 < kappa). `tree_seconds`
// (optional) receives the kd-tree build time; `has_coincident` (optional)
// whether some point has a neighbour at distance 0 (i.e. duplicates exist).
std::vector<int> KnnLists(const MatrixX3d& P, int kappa, std::vector<double>* mean_dist = nullptr,
                          double* tree_seconds = nullptr, bool* has_coincident = nullptr);

// The symmetric graph from directed κNN lists (n × kappa, -1 pads).
CsrGraph SymmetrizeKnn(const std::vector<int>& knn, int n, int kappa,
                       const std::vector<std::uint8_t>* removed = nullptr);

// Step 2: greedy maximal k-hop independent set: nodes are considered in
// increasing id (or in the order `priority` lists them, a permutation of the
// nodes), sites are returned in that order; every pair is at least k hops
// apart, every node (not skipped) within k-1 hops of a site. Nodes with
// skip[v] set are never sites (may be null).
std::vector<int> GreedyKHopIndependentSet(const CsrGraph& g, int k,
                                          const std::vector<std::uint8_t>* skip = nullptr,
                                          const std::vector<int>* priority = nullptr);

// Step 3: per node, the index into `sites` of its hop-nearest site (ties: the
// smaller index; `sites` sorted by id makes that the smaller node id); -1 for
// nodes no site reaches. `hops` (optional) receives the hop distance (-1).
std::vector<int> GraphVoronoiCells(const CsrGraph& g, const std::vector<int>& sites,
                                   std::vector<int>* hops = nullptr);

// Step 4: the combinatorial Delaunay map on site indices.
struct CombinatorialDelaunayMap {
  int num_sites = 0;
  std::vector<std::array<int, 2>> edges;  // (s, t), s < t, sorted
  std::vector<int> boundary;              // b(S,T) + b(T,S) of each edge (> a)
};
CombinatorialDelaunayMap BuildCombinatorialDelaunayMap(const CsrGraph& g,
                                                       const std::vector<int>& cell,
                                                       int num_sites, int a);

// Step 5: faces of the CDM as elementary cycles by increasing length.
struct FaceEnumeration {
  std::vector<std::vector<int>> faces;  // site indices, in acceptance order
  std::vector<std::uint8_t> edge_use;   // per CDM edge: number of faces (0..2)
  std::int64_t truncated_searches = 0;  // cycle searches stopped by the budget
};
FaceEnumeration EnumerateFaces(const CombinatorialDelaunayMap& cdm, int max_face_size,
                               std::int64_t search_budget);

struct GraphVoronoiOptions {
  int kappa = 15;          // κ nearest neighbours per point (paper §3: 15)
  int k = 5;               // hop distance of the independent set (paper §4.2: 5)
  // A cloud too small for k (the faces of steps 2-5 use fewer than 4 sites:
  // no face, or a single triangle) is rerun with k-1, k-2, ..., 2 and the
  // first k whose faces use >= 4 sites is kept (stats.k_used). Clouds for
  // which k spans a surface are untouched (the paper's result). Off: the
  // requested k only (an InputError when it spans no surface).
  bool adapt_k = true;
  int a = 7;               // adjacency threshold: b12 + b21 > a (paper §3: 7), in [0, 1e6]
  int max_face_size = 8;   // longest cycle enumerated as a face (paper: faces < 5 in practice)
  std::int64_t cycle_search_budget = 200000;  // DFS steps per start edge and length, in [1, 1e9]
  bool merge_duplicates = true;  // bit-identical points become one node
  double outlier_ratio = 0.0;    // 0 = keep all points (paper); else in [1, 1e12], see header comment
  bool triangulate = true;       // triangulate faces with more than three vertices
  bool orient = true;            // consistent orientation, components outward (signed volume)
  enum class VertexPosition { kSite, kCellMean } vertex_position = VertexPosition::kSite;
  static constexpr EnumName<VertexPosition> kVertexPositionNames[] = {{VertexPosition::kSite, "site"},
                                                                      {VertexPosition::kCellMean, "cell_mean"}};
  // Throws OptionError naming the option and its allowed range.
  void Check() const;
};

struct GraphVoronoiStats {
  // Wall times in seconds (the paper's Table 1 columns, where they exist).
  double prep_s = 0;         // validation, duplicate merging
  double kdtree_s = 0;       // kd-tree build (the paper's "Octr"), part of knn_s
  double knn_s = 0;          // kd-tree + batched κNN queries + symmetric graph ("Octr"+"Ngb")
  double mis_s = 0;          // "Mis"
  double voronoi_s = 0;      // "Vor"
  double cdm_s = 0;          // "Cdm"
  double cycles_s = 0;       // "Cyc"
  double orient_s = 0;       // orientation (ours)
  double triangulate_s = 0;  // triangulation of larger faces (ours)
  double total_s = 0;
  // Counts.
  std::int64_t input_points = 0, duplicates = 0, outliers_removed = 0;
  std::int64_t graph_edges = 0;
  int sites = 0;              // |S| = output vertices
  int k_used = 0;             // hop distance of the result (< opt.k only after adapt_k)
  std::vector<int> k_attempts;  // every k tried, in order (last = k_used)
  int cdm_vertices = 0;       // sites with at least one CDM edge
  std::int64_t cdm_edges = 0;
  std::int64_t faces = 0;     // faces before triangulation
  std::int64_t triangles_before = 0;  // faces of three vertices before triangulation
  std::vector<std::int64_t> faces_by_size;  // index = face size
  double pct_triangles = 0;   // 100 * triangles_before / faces
  double genus_value = 0;     // paper eq. 4.2: (2 - |V_CDM| + |E_CDM| - F) / 2
  std::int64_t unused_edges = 0;    // CDM edges in no face (paper Fig. 8's red edges)
  std::int64_t boundary_edges = 0;  // CDM edges in exactly one face
  std::int64_t truncated_searches = 0;
  std::int64_t orientation_conflicts = 0;  // shared edges traversed the same way after propagation
  int face_components = 0;         // edge-connected components of faces
  int closed_components = 0;
  std::int64_t forced_diagonals = 0;  // triangulation diagonals that repeat an existing edge
                                      // (unavoidable: each makes a non-manifold edge)
  std::int64_t output_triangles = 0;
};

struct GraphVoronoiResult {
  Mesh mesh;                              // vertices = sites; triangles (!triangulate: only the
                                          // faces that were triangles, larger ones left open)
  std::vector<int> sites;                 // input row of each vertex
  std::vector<std::vector<int>> polygons; // faces before triangulation (vertex indices, oriented)
  std::vector<int> point_vertex;          // per input row: its cell's vertex (-1 = removed outlier)
  GraphVoronoiStats stats;
};

// The whole algorithm. Throws InputError on unusable input (see above),
// OptionError on bad options.
GraphVoronoiResult ReconstructGraphVoronoi(const MatrixX3d& P, const GraphVoronoiOptions& opt = {});

}  // namespace arcs
