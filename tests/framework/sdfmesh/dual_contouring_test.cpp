#include "framework/sdfmesh/dual_contouring.h"

#include "framework/sdfmesh/dc_internal.h"
#include "framework/util/rng.h"

#include <Eigen/Geometry>

#include "framework/error.h"
#include "framework/geometry/marching_cubes.h"
#include "framework/spatial/topology.h"
#include "framework/util/parallel.h"
#include "tests/framework/sdfmesh/sdfmesh_test_fields.h"

#include <gtest/gtest.h>

#include <cmath>

namespace arcs {
namespace {

using testing::BoxSdf;
using testing::GridSamples;
using testing::SphereSdf;
using testing::TorusSdf;

double MaxRadiusError(const Mesh& m, double r) {
  double e = 0;
  for (int v = 0; v < m.NumVertices(); ++v) e = std::max(e, std::abs(m.V.row(v).norm() - r));
  return e;
}

TEST(DualContouringTest, SphereIsClosedGenusZeroOutwardAndOnTheSurface) {
  const double r = 0.6;
  const SdfSamples s = GridSamples(20, -1, 1, [&](const Vec3& p) { return SphereSdf(p, r); });
  DualContouringStats st;
  const Mesh m = DualContouring(s.values, *s.grid, {}, &st);
  const Topology t = ComputeTopology(m);
  EXPECT_TRUE(t.closed);
  EXPECT_TRUE(t.manifold);
  EXPECT_TRUE(t.oriented);
  EXPECT_EQ(t.genus, 0);
  EXPECT_EQ(t.degenerate_faces, 0);
  EXPECT_GT(t.volume, 0.0);  // outward
  // Enclosed volume within 2 % of the ball's.
  // Flat faces between vertices near the sphere: the volume is a little low.
  EXPECT_NEAR(t.volume, 4.0 / 3.0 * M_PI * r * r * r, 0.04 * 4.0 / 3.0 * M_PI * r * r * r);
  // Linear interpolation and tangent planes of a radius-0.6 sphere at h = 0.1
  // are off by O(h^2 / r) ~ 0.002; allow 0.01 (a tenth of a cell).
  EXPECT_LT(MaxRadiusError(m, r), 0.01);
  EXPECT_EQ(st.multi_sheet_cells, 0);
  EXPECT_EQ(st.quads * 2, m.NumFaces());
}

// A linear field is reproduced exactly: every Hermite point and normal is
// exact, so every vertex lies on the plane (QEF of rank 1: the mass point
// projected onto the plane, inside its cell).
TEST(DualContouringTest, PlanesAreReproducedExactly) {
  const Vec3 n = Vec3(0.3, -0.5, 0.8).normalized();
  const SdfSamples s = GridSamples(10, -1, 1, [&](const Vec3& p) { return n.dot(p) - 0.123; });
  for (auto normals : {DualContouringOptions::Normals::kTrilinear, DualContouringOptions::Normals::kEdge}) {
    DualContouringOptions o;
    o.normals = normals;
    const Mesh m = DualContouring(s.values, *s.grid, o);
    ASSERT_GT(m.NumFaces(), 0);
    for (int v = 0; v < m.NumVertices(); ++v) EXPECT_NEAR(n.dot(m.V.row(v).transpose()), 0.123, 1e-12);
    // Faces wound towards +n (the positive side).
    for (int f = 0; f < m.NumFaces(); ++f) {
      const Vec3 a = m.V.row(m.F(f, 0)), b = m.V.row(m.F(f, 1)), c = m.V.row(m.F(f, 2));
      EXPECT_GT((b - a).cross(c - a).dot(n), 0.0);
    }
  }
}

TEST(DualContouringTest, TrilinearGradientIsExactOnTrilinearFields) {
  auto f = [](const Vec3& p) { return 0.5 + p.x() - 2 * p.y() + 0.7 * p.x() * p.y() * p.z() + 0.3 * p.y() * p.z(); };
  const SdfSamples s = GridSamples(4, -1, 1, f);
  const dc_detail::DcGrid g = dc_detail::BuildDcGrid(s.values, *s.grid, 0.0, false);
  const std::int64_t cell = 1 + 4 * (2 + 4 * 3);  // cell (1, 2, 3): [-0.5, 0] x [0, 0.5] x [0.5, 1]
  const Vec3 x(-0.2, 0.3, 0.9);
  const Vec3 want(1 + 0.7 * x.y() * x.z(), -2 + 0.7 * x.x() * x.z() + 0.3 * x.z(), 0.7 * x.x() * x.y() + 0.3 * x.y());
  EXPECT_LT((dc_detail::TrilinearGradient(s.values, g, cell, x) - want).norm(), 1e-12);
  EXPECT_EQ(g.CellOf(x), cell);
}

TEST(DualContouringTest, BoxKeepsMoreOfItsCornersThanMarchingCubes) {
  const Vec3 b(0.43, 0.37, 0.31);  // corners inside cells, not on grid lines
  const SdfSamples s = GridSamples(20, -1, 1, [&](const Vec3& p) { return BoxSdf(p, b); });
  const Mesh dc = DualContouring(s.values, *s.grid);
  const Topology t = ComputeTopology(dc);
  EXPECT_TRUE(t.closed);
  EXPECT_EQ(t.genus, 0);
  EXPECT_GT(t.volume, 0.0);
  // Every vertex within a quarter cell of the box.
  for (int v = 0; v < dc.NumVertices(); ++v) EXPECT_LT(std::abs(BoxSdf(dc.V.row(v).transpose(), b)), 0.025);
}

TEST(DualContouringTest, TorusHasGenusOne) {
  const SdfSamples s = GridSamples(24, -1, 1, [](const Vec3& p) { return TorusSdf(p, 0.5, 0.2); });
  for (bool manifold : {false, true}) {
    DualContouringOptions o;
    o.manifold = manifold;
    const Topology t = ComputeTopology(DualContouring(s.values, *s.grid, o));
    EXPECT_TRUE(t.closed);
    EXPECT_EQ(t.genus, 1);
    EXPECT_GT(t.volume, 0.0);
  }
}

// A random field (boundary nodes outside, so the surface is closed) has many
// cells holding two or more sheets. Classic DC joins them at one vertex
// (non-manifold); manifold DC gives MC's topology: the dual of MC's patches
// has MC's components and Euler characteristic (patches - face segments +
// crossed edges), except where two face segments join the same two sheets.
TEST(DualContouringTest, ManifoldOptionSplitsMultiSheetCellsLikeMarchingCubes) {
  Rng rng(11);
  SdfSamples s = GridSamples(9, -1, 1, [&](const Vec3& p) {
    return p.cwiseAbs().maxCoeff() > 0.99 ? 1.0 : rng.Uniform(-1.0, 1.0);
  });
  DualContouringStats classic_st, manifold_st;
  const Mesh classic = DualContouring(s.values, *s.grid, {}, &classic_st);
  DualContouringOptions o;
  o.manifold = true;
  const Mesh manifold = DualContouring(s.values, *s.grid, o, &manifold_st);
  ASSERT_GT(classic_st.multi_sheet_cells, 0) << "the field must have cells holding two sheets";
  const Topology tc = ComputeTopology(classic), tm = ComputeTopology(manifold);
  const Topology tmc = ComputeTopology(MarchingCubes(s.values, *s.grid));
  // Classic DC here: 159 non-manifold edges and 8 non-manifold vertices;
  // manifold DC: only where one MC sheet meets both segments of an ambiguous
  // face (the tunnel case) does an edge get four faces (1 edge for this seed).
  EXPECT_GT(tc.nonmanifold_edges, 100);
  EXPECT_LE(tm.nonmanifold_edges * 50, tc.nonmanifold_edges);
  EXPECT_EQ(tm.nonmanifold_vertices, 0);
  EXPECT_TRUE(tm.closed);
  EXPECT_EQ(tm.components, tmc.components);
  EXPECT_NEAR(tm.euler, tmc.euler, tm.nonmanifold_edges);
  EXPECT_GT(manifold_st.vertices, classic_st.vertices);
}

TEST(DualContouringTest, TrilinearNormalsAndNoClampAlsoWork) {
  const SdfSamples s = GridSamples(12, -1, 1, [](const Vec3& p) { return SphereSdf(p, 0.55); });
  DualContouringOptions o;
  o.normals = DualContouringOptions::Normals::kTrilinear;
  o.clamp_to_cell = false;
  const Mesh m = DualContouring(s.values, *s.grid, o);
  EXPECT_TRUE(ComputeTopology(m).closed);
  EXPECT_LT(MaxRadiusError(m, 0.55), 0.02);
}

TEST(DualContouringTest, SameMeshAtOneAndTwoThreads) {
  const SdfSamples s = GridSamples(30, -1, 1, [](const Vec3& p) { return TorusSdf(p, 0.45, 0.18); });
  Mesh a, b;
  {
    ThreadLimit l(1);
    a = DualContouring(s.values, *s.grid);
  }
  {
    ThreadLimit l(2);
    b = DualContouring(s.values, *s.grid);
  }
  EXPECT_EQ(a.V, b.V);
  EXPECT_EQ(a.F, b.F);
}

TEST(DualContouringTest, BadInputAndOptionsAreClearErrors) {
  SdfSamples s = GridSamples(4, -1, 1, [](const Vec3& p) { return SphereSdf(p, 0.5); });
  VectorXd v = s.values;
  v[7] = NAN;
  EXPECT_THROW(DualContouring(v, *s.grid), Error);
  EXPECT_THROW(DualContouring(s.values.head(10), *s.grid), Error);
  GridInfo flat = *s.grid;
  flat.dims[2] = 1;
  EXPECT_THROW(DualContouring(s.values.head(25), flat), Error);
  DualContouringOptions o;
  o.svd_threshold = 1.0;
  EXPECT_THROW(DualContouring(s.values, *s.grid, o), OptionError);
}

}  // namespace
}  // namespace arcs
