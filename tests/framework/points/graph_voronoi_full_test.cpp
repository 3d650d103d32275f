// Graph Voronoi at full resolution (framework/points/graph_voronoi_full.h):
// every point becomes a vertex, the coarse topology is kept.
#include "framework/points/graph_voronoi_full.h"

#include "framework/error.h"
#include "framework/geometry/builtin_shapes.h"
#include "framework/geometry/surface_sampling.h"
#include "framework/io/points_io.h"
#include "framework/points/delaunay_2d.h"
#include "framework/spatial/topology.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <map>
#include <set>
#include <vector>

namespace arcs {
namespace {

// Closed, manifold, outward, one component, the given genus, Euler's formula,
// and every vertex one of the input points.
void ExpectFullResolution(const MatrixX3d& P, const Mesh& m, int genus) {
  const Topology t = ComputeTopology(m);
  EXPECT_TRUE(t.closed);
  EXPECT_TRUE(t.manifold);
  EXPECT_TRUE(t.oriented);
  EXPECT_EQ(t.components, 1);
  EXPECT_EQ(t.genus, genus);
  EXPECT_GT(t.volume, 0.0);
  EXPECT_EQ(t.referenced_vertices, m.NumVertices());
  EXPECT_EQ(m.NumFaces(), 2 * m.NumVertices() - 4 + 4 * genus);  // V - E + F = 2 - 2g, E = 3F/2
  std::set<std::array<double, 3>> input;
  for (int i = 0; i < P.rows(); ++i) input.insert({P(i, 0), P(i, 1), P(i, 2)});
  for (int i = 0; i < m.NumVertices(); ++i)
    ASSERT_TRUE(input.count({m.V(i, 0), m.V(i, 1), m.V(i, 2)})) << "vertex " << i << " is not an input point";
}

TEST(GraphVoronoiFull, SphereEveryPointIsAVertexAndTopologyKept) {
  const MatrixX3d P = SampleSurfaceUniform(MakeIcosphere(1.0, 5), 15000, 7);
  const GraphVoronoiResult coarse = ReconstructGraphVoronoi(P);
  ASSERT_LT(coarse.mesh.NumVertices(), 1000);  // the coarse mesh keeps ~1 point in 50
  FullResolutionStats st;
  const Mesh m = RefineGraphVoronoi(P, coarse, {}, &st);
  ExpectFullResolution(P, m, 0);
  EXPECT_GE(st.pct_points, 99.0);
  EXPECT_EQ(st.vertices, m.NumVertices());
  EXPECT_EQ(st.dropped_points, 0);
  EXPECT_EQ(st.interior_points + st.edge_points + static_cast<std::int64_t>(coarse.sites.size()) - st.merged_points,
            st.vertices);
  // Vertices lie on the unit sphere, and most triangles agree with their coarse face.
  for (int i = 0; i < m.NumVertices(); ++i) EXPECT_NEAR(m.V.row(i).norm(), 1.0, 0.01);
  EXPECT_LT(st.folded_triangles, m.NumFaces() / 20);
}

TEST(GraphVoronoiFull, TorusKeepsGenusOne) {
  const MatrixX3d P = SampleSurfaceUniform(MakeTorus(1.0, 0.4, 200, 100), 25000, 3);
  FullResolutionStats st;
  const Mesh m = RefineGraphVoronoi(P, ReconstructGraphVoronoi(P), {}, &st);
  ExpectFullResolution(P, m, 1);
  EXPECT_GE(st.pct_points, 99.0);
}

TEST(GraphVoronoiFull, DuplicatesBecomeOneVertex) {
  const MatrixX3d S = SampleSurfaceUniform(MakeIcosphere(1.0, 5), 8000, 5);
  MatrixX3d P(S.rows() + 500, 3);
  P.topRows(S.rows()) = S;
  for (int i = 0; i < 500; ++i) P.row(S.rows() + i) = S.row(7 * i);  // 500 repeated rows
  FullResolutionStats st;
  const Mesh m = RefineGraphVoronoi(P, ReconstructGraphVoronoi(P), {}, &st);
  ExpectFullResolution(P, m, 0);
  EXPECT_GE(st.merged_points, 500);
  EXPECT_LE(m.NumVertices(), S.rows());
  EXPECT_GE(m.NumVertices(), S.rows() * 99 / 100);
}

TEST(GraphVoronoiFull, ClearErrors) {
  const MatrixX3d P = SampleSurfaceUniform(MakeIcosphere(1.0, 4), 3000, 1);
  const GraphVoronoiResult coarse = ReconstructGraphVoronoi(P);
  const MatrixX3d Q = P.topRows(2000);
  testing::ExpectInputError([&] { RefineGraphVoronoi(Q, coarse); }, {"full_resolution", "does not belong"});
  FullResolutionOptions bad;
  bad.interior_margin = 0;
  EXPECT_THROW(RefineGraphVoronoi(P, coarse, bad), OptionError);
}

TEST(Delaunay2D, CollinearEdgePointsSplitTheHull) {
  // A triangle with two points exactly on its hypotenuse and one inside: every
  // hull segment between consecutive boundary points is an edge.
  const std::vector<double> x = {0, 1, 0, 0.75, 0.25, 0.2, 0.75}, y = {0, 0, 1, 0.25, 0.75, 0.2, 0.25};
  int merged = 0;
  const auto t = points_detail::Delaunay2D(x, y, &merged);
  EXPECT_EQ(merged, 1);  // the repeated (0.75, 0.25)
  // 6 distinct points, 5 on the hull: 2n - 2 - h = 12 - 2 - 5 = 5 triangles.
  EXPECT_EQ(t.size(), 5u);
  std::map<std::pair<int, int>, int> edges;
  for (const auto& f : t)
    for (int j = 0; j < 3; ++j) {
      // counter-clockwise: each directed edge once
      EXPECT_EQ(++edges[std::make_pair(f[j], f[(j + 1) % 3])], 1);
      EXPECT_NE(f[j], 6);
    }
  for (auto [a, b] : std::vector<std::pair<int, int>>{{1, 3}, {3, 4}, {4, 2}}) EXPECT_EQ(edges.count({a, b}), 1u);
}

TEST(GraphVoronoiFull, BunnyScanAtFullResolution) {
  ARCS_REQUIRE_SHARED_DATA();
  const PointCloud pc = ReadPointCloud(testing::SharedData("scans/stanford_bunny_range/bun_zipper.ply"));
  FullResolutionStats st;
  const Mesh m = RefineGraphVoronoi(pc.P, ReconstructGraphVoronoi(pc.P), {}, &st);
  const Topology t = ComputeTopology(m);
  EXPECT_GE(st.pct_points, 90.0);  // issue 14, criterion 6
  EXPECT_TRUE(t.closed);
  EXPECT_TRUE(t.manifold);
  EXPECT_EQ(t.genus, 0);
  EXPECT_EQ(t.components, 1);
}

}  // namespace
}  // namespace arcs
