// Graph-Voronoi reconstruction (framework/points/graph_voronoi.h): the steps
// on hand-made graphs, whole reconstructions of sampled built-in shapes with
// known genus, determinism, degenerate input, and the paper's bunny claim.
#include "framework/points/graph_voronoi.h"

#include "framework/error.h"
#include "framework/geometry/builtin_shapes.h"
#include "framework/geometry/surface_sampling.h"
#include "framework/io/points_io.h"
#include "framework/spatial/topology.h"
#include "framework/util/parallel.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>
#include <vector>

namespace arcs {
namespace {

// Hop distances from `s` (BFS), -1 = unreachable.
std::vector<int> Bfs(const CsrGraph& g, int s) {
  std::vector<int> d(g.NumNodes(), -1), q{s};
  d[s] = 0;
  for (std::size_t h = 0; h < q.size(); ++h)
    for (auto e = g.offsets[q[h]]; e < g.offsets[q[h] + 1]; ++e)
      if (d[g.adj[e]] < 0) {
        d[g.adj[e]] = d[q[h]] + 1;
        q.push_back(g.adj[e]);
      }
  return d;
}

CsrGraph GraphFromEdges(int n, const std::vector<std::array<int, 2>>& edges) {
  std::vector<std::vector<int>> nb(n);
  for (auto [a, b] : edges) {
    nb[a].push_back(b);
    nb[b].push_back(a);
  }
  CsrGraph g;
  g.offsets.push_back(0);
  for (auto& l : nb) {
    std::sort(l.begin(), l.end());
    g.adj.insert(g.adj.end(), l.begin(), l.end());
    g.offsets.push_back(static_cast<std::int64_t>(g.adj.size()));
  }
  return g;
}

MatrixX3d SphereSamples(int count, std::uint64_t seed = 7) {
  return SampleSurfaceUniform(MakeIcosphere(1.0, 5), count, seed);
}

TEST(GraphVoronoiKnn, SymmetricGraphContainsEveryKnnEdge) {
  const MatrixX3d P = SphereSamples(2000);
  const int kappa = 6;
  const std::vector<int> knn = KnnLists(P, kappa);
  const CsrGraph g = SymmetrizeKnn(knn, 2000, kappa);
  auto has = [&](int a, int b) {
    return std::binary_search(g.adj.begin() + g.offsets[a], g.adj.begin() + g.offsets[a + 1], b);
  };
  for (int v = 0; v < 2000; ++v) {
    EXPECT_GE(g.Degree(v), kappa);
    for (int j = 0; j < kappa; ++j) {
      const int t = knn[v * kappa + j];
      ASSERT_NE(t, v);
      EXPECT_TRUE(has(v, t) && has(t, v));
    }
  }
  // kNN lists are the true nearest (brute force for a few points).
  for (int v = 0; v < 2000; v += 397) {
    std::vector<std::pair<double, int>> all;
    for (int u = 0; u < 2000; ++u)
      if (u != v) all.push_back({(P.row(u) - P.row(v)).squaredNorm(), u});
    std::sort(all.begin(), all.end());
    std::set<int> want, got;
    for (int j = 0; j < kappa; ++j) {
      want.insert(all[j].second);
      got.insert(knn[v * kappa + j]);
    }
    EXPECT_EQ(want, got);
  }
}

TEST(GraphVoronoiSteps, IndependentSetIsKHopStableAndMaximal) {
  const CsrGraph g = BuildKnnGraph(SphereSamples(1500), 8);
  for (int k : {2, 4}) {
    const std::vector<int> sites = GreedyKHopIndependentSet(g, k);
    ASSERT_FALSE(sites.empty());
    EXPECT_EQ(sites.front(), 0);  // greedy in id order
    std::vector<int> nearest(g.NumNodes(), std::numeric_limits<int>::max());
    for (int s : sites) {
      const auto d = Bfs(g, s);
      for (int t : sites) {
        if (t != s) {
          EXPECT_GE(d[t], k) << "sites " << s << ", " << t;
        }
      }
      for (int v = 0; v < g.NumNodes(); ++v)
        if (d[v] >= 0) nearest[v] = std::min(nearest[v], d[v]);
    }
    for (int v = 0; v < g.NumNodes(); ++v) EXPECT_LE(nearest[v], k - 1) << "node " << v;
  }
}

TEST(GraphVoronoiSteps, CellsAreHopNearestWithTiesToSmallerId) {
  const CsrGraph g = BuildKnnGraph(SphereSamples(1200), 6);
  const std::vector<int> sites = GreedyKHopIndependentSet(g, 4);
  std::vector<int> hops;
  const std::vector<int> cell = GraphVoronoiCells(g, sites, &hops);
  std::vector<std::vector<int>> d;
  for (int s : sites) d.push_back(Bfs(g, s));
  for (int v = 0; v < g.NumNodes(); ++v) {
    int best = -1;
    for (int i = 0; i < static_cast<int>(sites.size()); ++i)
      if (d[i][v] >= 0 && (best < 0 || d[i][v] < d[best][v])) best = i;  // first = smallest id
    ASSERT_EQ(cell[v], best) << "node " << v;
    EXPECT_EQ(hops[v], d[best][v]);
  }
}

TEST(GraphVoronoiSteps, CdmCountsBoundaryNodesFromBothSides) {
  // Cells: A = {0,1,2}, B = {3,4}, C = {5}. Edges A-B: 0-3, 1-3, 2-4, 1-4 ->
  // b(A,B) = |{0,1,2}| = 3, b(B,A) = |{3,4}| = 2: total 5. B-C: 4-5 -> 1 + 1.
  const CsrGraph g = GraphFromEdges(
      6, {{0, 1}, {1, 2}, {0, 3}, {1, 3}, {2, 4}, {1, 4}, {3, 4}, {4, 5}});
  const std::vector<int> cell = {0, 0, 0, 1, 1, 2};
  const auto cdm4 = BuildCombinatorialDelaunayMap(g, cell, 3, 4);
  ASSERT_EQ(cdm4.edges.size(), 1u);
  EXPECT_EQ(cdm4.edges[0], (std::array<int, 2>{0, 1}));
  EXPECT_EQ(cdm4.boundary[0], 5);
  EXPECT_TRUE(BuildCombinatorialDelaunayMap(g, cell, 3, 5).edges.empty());  // strictly greater
  const auto cdm1 = BuildCombinatorialDelaunayMap(g, cell, 3, 1);
  ASSERT_EQ(cdm1.edges.size(), 2u);
  EXPECT_EQ(cdm1.boundary[1], 2);
}

CombinatorialDelaunayMap Cdm(int n, std::vector<std::array<int, 2>> e) {
  for (auto& x : e)
    if (x[0] > x[1]) std::swap(x[0], x[1]);
  std::sort(e.begin(), e.end());
  CombinatorialDelaunayMap c;
  c.num_sites = n;
  c.edges = e;
  c.boundary.assign(e.size(), 10);
  return c;
}

TEST(GraphVoronoiSteps, FacesOfPolyhedraGraphs) {
  // Octahedron: 8 triangles; cube: 6 quadrilaterals (its 6-cycles are not
  // faces: every edge is in two quads by then).
  const auto oct = EnumerateFaces(
      Cdm(6, {{0, 1}, {0, 2}, {0, 3}, {0, 4}, {5, 1}, {5, 2}, {5, 3}, {5, 4}, {1, 2}, {2, 3}, {3, 4}, {4, 1}}),
      8, 100000);
  EXPECT_EQ(oct.faces.size(), 8u);
  for (auto u : oct.edge_use) EXPECT_EQ(u, 2);
  const auto cube = EnumerateFaces(Cdm(8, {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6}, {6, 7}, {7, 4},
                                           {0, 4}, {1, 5}, {2, 6}, {3, 7}}),
                                   8, 100000);
  ASSERT_EQ(cube.faces.size(), 6u);
  for (const auto& f : cube.faces) EXPECT_EQ(f.size(), 4u);
  for (auto u : cube.edge_use) EXPECT_EQ(u, 2);
  // A pentagon with a pendant edge: one face, the pendant edge in none.
  const auto pent = EnumerateFaces(Cdm(6, {{0, 1}, {1, 2}, {2, 3}, {3, 4}, {4, 0}, {4, 5}}), 4, 100000);
  EXPECT_TRUE(pent.faces.empty());  // longer than max_face_size
  const auto pent5 = EnumerateFaces(Cdm(6, {{0, 1}, {1, 2}, {2, 3}, {3, 4}, {4, 0}, {4, 5}}), 5, 100000);
  ASSERT_EQ(pent5.faces.size(), 1u);
  EXPECT_EQ(pent5.edge_use.back(), 0);  // (4,5)
}

void ExpectClosedGenus(const GraphVoronoiResult& r, int genus) {
  const Topology t = ComputeTopology(r.mesh);
  EXPECT_TRUE(t.closed);
  EXPECT_TRUE(t.manifold);
  EXPECT_TRUE(t.oriented);
  EXPECT_EQ(t.components, 1);
  EXPECT_EQ(t.genus, genus);
  EXPECT_GT(t.volume, 0.0);  // outward
  // The paper's genus value counts every CDM edge, also those in no face
  // (hence its half-integers): (2 - V + E - F) / 2 = genus + unused / 2.
  EXPECT_EQ(r.stats.genus_value, genus + r.stats.unused_edges / 2.0);
  EXPECT_EQ(r.stats.boundary_edges, 0);
  EXPECT_EQ(r.stats.orientation_conflicts, 0);
}

TEST(GraphVoronoi, SampledSphereIsClosedGenus0) {
  const MatrixX3d P = SphereSamples(15000);
  const GraphVoronoiResult r = ReconstructGraphVoronoi(P);
  ExpectClosedGenus(r, 0);
  EXPECT_GT(r.stats.pct_triangles, 85.0);
  // Vertices are input points (sites), all on the unit sphere's mesh.
  ASSERT_EQ(r.mesh.NumVertices(), static_cast<int>(r.sites.size()));
  for (int i = 0; i < r.mesh.NumVertices(); ++i) {
    EXPECT_EQ(r.mesh.V.row(i), P.row(r.sites[i]));
    EXPECT_NEAR(r.mesh.V.row(i).norm(), 1.0, 0.01);
  }
  // Every input point maps to a vertex (its cell).
  for (int v : r.point_vertex) ASSERT_TRUE(v >= 0 && v < r.mesh.NumVertices());
}

TEST(GraphVoronoi, SampledTorusIsClosedGenus1) {
  const MatrixX3d P = SampleSurfaceUniform(MakeTorus(1.0, 0.4, 200, 100), 25000, 3);
  ExpectClosedGenus(ReconstructGraphVoronoi(P), 1);
}

TEST(GraphVoronoi, DeterministicAcrossRunsAndThreads) {
  const MatrixX3d P = SphereSamples(8000, 11);
  GraphVoronoiResult a, b;
  {
    ThreadLimit one(1);
    a = ReconstructGraphVoronoi(P);
  }
  {
    ThreadLimit two(2);
    b = ReconstructGraphVoronoi(P);
  }
  EXPECT_EQ(a.sites, b.sites);
  EXPECT_EQ(a.polygons, b.polygons);
  EXPECT_TRUE(a.mesh.F == b.mesh.F);
  EXPECT_TRUE(a.mesh.V == b.mesh.V);
}

TEST(GraphVoronoi, BadInputIsAClearError) {
  using testing::ExpectInputError;
  MatrixX3d three(3, 3);
  three << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  ExpectInputError([&] { ReconstructGraphVoronoi(three); }, {"graph_voronoi", "at least 4 points, got 3"});
  MatrixX3d nan = SphereSamples(100);
  nan(42, 1) = std::numeric_limits<double>::quiet_NaN();
  ExpectInputError([&] { ReconstructGraphVoronoi(nan); }, {"point 42", "non-finite"});
  MatrixX3d inf = SphereSamples(100);
  inf(7, 2) = std::numeric_limits<double>::infinity();
  ExpectInputError([&] { ReconstructGraphVoronoi(inf); }, {"point 7", "non-finite"});
  MatrixX3d same = MatrixX3d::Constant(50, 3, 0.5);
  ExpectInputError([&] { ReconstructGraphVoronoi(same); }, {"all 50 points are at one position"});
  MatrixX3d few = MatrixX3d::Zero(10, 3);
  few(9, 0) = 1;
  few(8, 1) = 1;
  ExpectInputError([&] { ReconstructGraphVoronoi(few); }, {"only 3 distinct points among 10"});
  GraphVoronoiOptions o;
  o.k = 0;
  EXPECT_THROW(ReconstructGraphVoronoi(SphereSamples(100), o), OptionError);
  o = {};
  o.outlier_ratio = 0.5;
  EXPECT_THROW(ReconstructGraphVoronoi(SphereSamples(100), o), OptionError);
}

TEST(GraphVoronoi, DuplicatesAreMergedAndGiveTheSameSurface) {
  const MatrixX3d P = SphereSamples(10000, 5);
  // Every third point repeated (appended), one point eight more times.
  const int n = static_cast<int>(P.rows());
  MatrixX3d D(n + n / 3 + 8, 3);
  D.topRows(n) = P;
  for (int i = 0; i < n / 3; ++i) D.row(n + i) = P.row(3 * i);
  for (int i = 0; i < 8; ++i) D.row(n + n / 3 + i) = P.row(5);
  const GraphVoronoiResult a = ReconstructGraphVoronoi(P), b = ReconstructGraphVoronoi(D);
  EXPECT_EQ(a.stats.duplicates, 0);
  EXPECT_EQ(b.stats.duplicates, n / 3 + 8);
  EXPECT_EQ(a.sites, b.sites);  // first occurrences keep their ids
  EXPECT_TRUE(a.mesh.F == b.mesh.F);
  for (int i = 0; i < n / 3; ++i) ASSERT_EQ(b.point_vertex[n + i], b.point_vertex[3 * i]);
  ExpectClosedGenus(b, 0);
}

TEST(GraphVoronoi, OutliersDocumentedResult) {
  // Six far outliers (3 radii out) appended to a sampled sphere. Kept (the
  // paper): they join the cells of the surface points nearest to them and are
  // not sites (ids after the surface's), the surface stays a closed sphere.
  // With outlier_ratio they are removed first and map to no vertex.
  const MatrixX3d S = SphereSamples(12000, 9);
  MatrixX3d P(S.rows() + 6, 3);
  P.topRows(S.rows()) = S;
  const double far[6][3] = {{3, 0, 0}, {-3, 0, 0}, {0, 3, 0}, {0, -3, 0}, {0, 0, 3}, {2, 2, 2}};
  for (int i = 0; i < 6; ++i) P.row(S.rows() + i) = Vec3(far[i][0], far[i][1], far[i][2]);
  const GraphVoronoiResult kept = ReconstructGraphVoronoi(P);
  ExpectClosedGenus(kept, 0);
  for (int s : kept.sites) EXPECT_LT(s, S.rows());
  GraphVoronoiOptions o;
  o.outlier_ratio = 10;
  const GraphVoronoiResult filtered = ReconstructGraphVoronoi(P, o);
  EXPECT_EQ(filtered.stats.outliers_removed, 6);
  for (int i = 0; i < 6; ++i) EXPECT_EQ(filtered.point_vertex[S.rows() + i], -1);
  ExpectClosedGenus(filtered, 0);
  EXPECT_EQ(filtered.sites, ReconstructGraphVoronoi(S).sites);
  // Outliers first in the id order become sites: each is a vertex off the
  // surface; the result is still reported honestly (topology as computed).
  MatrixX3d Q(P.rows(), 3);
  Q.topRows(6) = P.bottomRows(6);
  Q.bottomRows(S.rows()) = S;
  const GraphVoronoiResult first = ReconstructGraphVoronoi(Q);
  EXPECT_EQ(first.sites[0], 0);
  EXPECT_TRUE(filtered.mesh.V.rowwise().norm().maxCoeff() < 1.01);
  EXPECT_GT(first.mesh.V.rowwise().norm().maxCoeff(), 2.9);
}

TEST(GraphVoronoi, SmallSphereCloudAdaptsKToAClosedSurface) {
  // 200 points on the unit sphere: at the paper's k = 5 the k-hop subsample
  // has 3 sites, whose CDM gives at most one triangle (before adapt_k: an
  // open one-triangle mesh, or none). adapt_k reruns with smaller k; the
  // result is a closed genus-0 surface and says which k it used.
  const MatrixX3d P = SphereSamples(200, 3);
  GraphVoronoiOptions paper;
  paper.adapt_k = false;
  testing::ExpectInputError([&] { ReconstructGraphVoronoi(P, paper); },
                            {"graph_voronoi", "no surface", "200 points", "k=5"});
  const GraphVoronoiResult r = ReconstructGraphVoronoi(P);
  EXPECT_LT(r.stats.k_used, 5);
  EXPECT_GE(r.stats.k_used, 2);
  ASSERT_FALSE(r.stats.k_attempts.empty());
  EXPECT_EQ(r.stats.k_attempts.front(), 5);
  EXPECT_EQ(r.stats.k_attempts.back(), r.stats.k_used);
  EXPECT_GE(r.stats.sites, 4);
  ExpectClosedGenus(r, 0);
  for (int i = 0; i < r.mesh.NumVertices(); ++i) EXPECT_NEAR(r.mesh.V.row(i).norm(), 1.0, 0.01);
  // The result is the plain algorithm at that k.
  GraphVoronoiOptions at;
  at.k = r.stats.k_used;
  at.adapt_k = false;
  const GraphVoronoiResult same = ReconstructGraphVoronoi(P, at);
  EXPECT_EQ(same.sites, r.sites);
  EXPECT_TRUE(same.mesh.F == r.mesh.F);
}

TEST(GraphVoronoi, NormalCloudKeepsThePapersK) {
  // A dense sample gives faces at k = 5: one attempt, the same result with
  // adapt_k on or off.
  const MatrixX3d P = SphereSamples(15000);
  GraphVoronoiOptions off;
  off.adapt_k = false;
  const GraphVoronoiResult a = ReconstructGraphVoronoi(P), b = ReconstructGraphVoronoi(P, off);
  EXPECT_EQ(a.stats.k_used, 5);
  EXPECT_EQ(a.stats.k_attempts, std::vector<int>{5});
  EXPECT_EQ(a.sites, b.sites);
  EXPECT_EQ(a.polygons, b.polygons);
  EXPECT_TRUE(a.mesh.F == b.mesh.F);
}

TEST(GraphVoronoi, CloudTooSmallForAnyKIsAClearError) {
  // 10 distinct points: no k down to 2 spans a surface. The error names the
  // point count and what each k gave; no empty mesh comes back.
  const MatrixX3d P = SphereSamples(10, 4);
  testing::ExpectInputError([&] { ReconstructGraphVoronoi(P); },
                            {"graph_voronoi", "no surface", "10 points", "k=5", "k=2", "too small"});
}

TEST(GraphVoronoi, SmallPclScansFromTheSharedData) {
  // PCL's ~200-point bunny clouds (MANIFEST: pcl_bunny_small): k = 5 gave no
  // face on bun01/02/03; with adapt_k each gives a surface on >= 4 sites.
  ARCS_REQUIRE_SHARED_DATA();
  for (const char* name : {"bun01.pcd", "bun02.pcd", "bun03.pcd"}) {
    SCOPED_TRACE(name);
    const PointCloud pc = ReadPointCloud(testing::SharedData(std::string("scans/pcl_bunny_small/") + name));
    ASSERT_GE(pc.Size(), 190);
    const GraphVoronoiResult r = ReconstructGraphVoronoi(pc.P);
    EXPECT_LT(r.stats.k_used, 5);
    EXPECT_GT(r.mesh.NumFaces(), 0);
    EXPECT_GE(r.stats.sites, 4);
  }
}

TEST(GraphVoronoi, BunnyFromTheSharedData) {
  ARCS_REQUIRE_SHARED_DATA();
  const PointCloud pc = ReadPointCloud(testing::SharedData("scans/stanford_bunny_range/bun_zipper.ply"));
  ASSERT_EQ(pc.Size(), 35947);
  const GraphVoronoiResult r = ReconstructGraphVoronoi(pc.P);  // k = 5, a = 7, κ = 15
  ExpectClosedGenus(r, 0);
  EXPECT_GE(r.stats.pct_triangles, 90.0);  // paper Table 2: 95.3 %
}

}  // namespace
}  // namespace arcs
