#include "framework/spatial/topology.h"

#include "framework/error.h"
#include "tests/framework/spatial/spatial_test_meshes.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace arcs {
namespace {

using spatial_test::Concat;
using spatial_test::Icosphere;
using spatial_test::Torus;

TEST(Topology, SphereIsGenusZero) {
  const Mesh m = Icosphere(2);
  const Topology t = ComputeTopology(m);
  EXPECT_EQ(t.vertices, 162);
  EXPECT_EQ(t.referenced_vertices, 162);
  EXPECT_EQ(t.faces, 320);
  EXPECT_EQ(t.edges, 480);
  EXPECT_EQ(t.euler, 2);
  EXPECT_EQ(t.components, 1);
  EXPECT_EQ(t.boundary_edges, 0);
  EXPECT_EQ(t.nonmanifold_edges, 0);
  EXPECT_EQ(t.nonmanifold_vertices, 0);
  EXPECT_EQ(t.degenerate_faces, 0);
  EXPECT_TRUE(t.closed);
  EXPECT_TRUE(t.edge_manifold);
  EXPECT_TRUE(t.manifold);
  EXPECT_TRUE(t.oriented);
  EXPECT_EQ(t.genus, 0);
  // Inscribed polyhedron: slightly less than the sphere's area and volume.
  const Topology fine = ComputeTopology(Icosphere(4));
  EXPECT_NEAR(fine.area, 4 * std::numbers::pi, 0.03);
  EXPECT_LT(fine.area, 4 * std::numbers::pi);
  EXPECT_NEAR(fine.volume, 4.0 / 3.0 * std::numbers::pi, 0.02);
  EXPECT_LT(fine.volume, 4.0 / 3.0 * std::numbers::pi);
  EXPECT_GT(t.volume, 0.9 * 4.0 / 3.0 * std::numbers::pi);
}

TEST(Topology, TorusIsGenusOne) {
  const Topology t = ComputeTopology(Torus(1.0, 0.3, 30, 12));
  EXPECT_EQ(t.euler, 0);
  EXPECT_EQ(t.genus, 1);
  EXPECT_TRUE(t.closed && t.manifold && t.oriented);
  EXPECT_GT(t.volume, 0.0);
}

TEST(Topology, TwoSpheresAndSpherePlusTorus) {
  const Mesh a = Icosphere(1), b = Icosphere(2, 1.0, Vec3(5, 0, 0));
  const Topology t = ComputeTopology(Concat(a, b));
  EXPECT_EQ(t.components, 2);
  EXPECT_EQ(t.euler, 4);
  EXPECT_EQ(t.genus, 0);
  const Topology u = ComputeTopology(Concat(a, Torus(1.0, 0.3, 20, 10, Vec3(0, 5, 0))));
  EXPECT_EQ(u.components, 2);
  EXPECT_EQ(u.genus, 1);
  // Unreferenced vertices are counted in `vertices` only.
  Mesh c = a;
  c.V.conservativeResize(c.V.rows() + 3, 3);
  c.V.bottomRows(3).setConstant(9.0);
  const Topology v = ComputeTopology(c);
  EXPECT_EQ(v.vertices, a.NumVertices() + 3);
  EXPECT_EQ(v.referenced_vertices, a.NumVertices());
  EXPECT_EQ(v.components, 1);
  EXPECT_EQ(v.genus, 0);
}

TEST(Topology, OpenDiscHasBoundary) {
  // A fan of 8 triangles around the origin.
  Mesh m;
  m.V.resize(9, 3);
  m.V.row(0) << 0, 0, 0;
  for (int i = 0; i < 8; ++i)
    m.V.row(i + 1) << std::cos(i * std::numbers::pi / 4), std::sin(i * std::numbers::pi / 4), 0;
  m.F.resize(8, 3);
  for (int i = 0; i < 8; ++i) m.F.row(i) << 0, i + 1, (i + 1) % 8 + 1;
  const Topology t = ComputeTopology(m);
  EXPECT_EQ(t.boundary_edges, 8);
  EXPECT_EQ(t.edges, 16);
  EXPECT_EQ(t.euler, 1);
  EXPECT_FALSE(t.closed);
  EXPECT_TRUE(t.manifold);
  EXPECT_TRUE(t.oriented);
  EXPECT_EQ(t.genus, -1);
  EXPECT_NEAR(t.area, 8 * 0.5 * std::sin(std::numbers::pi / 4), 1e-12);
}

TEST(Topology, EdgeSharedByFourTriangles) {
  // Four fins around the edge (0,1).
  Mesh m;
  m.V.resize(6, 3);
  m.V << 0, 0, 0, 0, 0, 1, 1, 0, 0, 0, 1, 0, -1, 0, 0, 0, -1, 0;
  m.F.resize(4, 3);
  m.F << 0, 1, 2, 1, 0, 3, 0, 1, 4, 1, 0, 5;
  const Topology t = ComputeTopology(m);
  EXPECT_EQ(t.nonmanifold_edges, 1);
  EXPECT_FALSE(t.edge_manifold);
  EXPECT_FALSE(t.manifold);
  EXPECT_EQ(t.boundary_edges, 8);
  EXPECT_EQ(t.genus, -1);
}

TEST(Topology, TetrahedraSharingOneVertex) {
  Mesh tet;
  tet.V.resize(4, 3);
  tet.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  tet.F.resize(4, 3);
  tet.F << 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3;
  ASSERT_NEAR(ComputeTopology(tet).volume, 1.0 / 6.0, 1e-15);
  // Second tetrahedron mirrored through the origin, glued at vertex 0.
  Mesh m;
  m.V.resize(7, 3);
  m.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, -1, 0, 0, 0, -1, 0, 0, 0, -1;
  m.F.resize(8, 3);
  m.F << 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3,  // first
      0, 4, 5, 0, 6, 4, 0, 5, 6, 4, 6, 5;      // second (mirror: reversed)
  const Topology t = ComputeTopology(m);
  EXPECT_EQ(t.nonmanifold_vertices, 1);
  EXPECT_EQ(t.nonmanifold_edges, 0);
  EXPECT_TRUE(t.edge_manifold);
  EXPECT_FALSE(t.manifold);
  EXPECT_TRUE(t.closed);
  EXPECT_TRUE(t.oriented);
  EXPECT_EQ(t.components, 1);
  EXPECT_EQ(t.genus, -1);
  EXPECT_NEAR(t.volume, 2.0 / 6.0, 1e-15);
}

TEST(Topology, FlippedFaceIsNotOriented) {
  Mesh m = Icosphere(1);
  std::swap(m.F(3, 1), m.F(3, 2));
  const Topology t = ComputeTopology(m);
  EXPECT_FALSE(t.oriented);
  EXPECT_TRUE(t.closed);
  EXPECT_EQ(t.genus, -1);
}

TEST(Topology, DegenerateFaces) {
  Mesh m = Icosphere(1);
  const int n = m.NumFaces();
  m.F.conservativeResize(n + 2, 3);
  m.F.row(n) << 0, 0, 1;  // repeated index
  m.V.conservativeResize(m.V.rows() + 1, 3);
  m.V.row(m.V.rows() - 1) = 0.5 * (m.V.row(0) + m.V.row(1));
  m.F.row(n + 1) << 0, 1, static_cast<int>(m.V.rows()) - 1;  // collinear, zero area
  EXPECT_EQ(ComputeTopology(m).degenerate_faces, 2);
  EXPECT_EQ(ComputeTopology(Icosphere(1)).degenerate_faces, 0);
}

TEST(Topology, RejectsBadIndices) {
  Mesh m = Icosphere(1);
  m.F(0, 2) = -1;
  EXPECT_THROW(ComputeTopology(m), InputError);
  try {
    ComputeTopology(m);
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("face 0 has vertex index -1"), std::string::npos) << e.what();
  }
}

TEST(Topology, EmptyMesh) {
  const Topology t = ComputeTopology(Mesh{});
  EXPECT_EQ(t.faces, 0);
  EXPECT_EQ(t.components, 0);
  EXPECT_FALSE(t.closed);
  EXPECT_EQ(t.genus, -1);
}

TEST(Topology, TinyMeshesMatchManifest) {
  ARCS_REQUIRE_SHARED_DATA();
  const auto rows = spatial_test::ReadManifest(testing::SharedData("tiny/MANIFEST.tsv"));
  ASSERT_FALSE(rows.empty());
  for (const auto& row : rows) {
    SCOPED_TRACE(row.at("file"));
    const Mesh m = spatial_test::ReadObjVF(testing::SharedData("tiny/" + row.at("file")));
    const Topology t = ComputeTopology(m);
    EXPECT_EQ(t.genus, std::stoi(row.at("genus")));
    EXPECT_EQ(t.components, std::stoi(row.at("components")));
    EXPECT_EQ(t.boundary_edges, std::stoi(row.at("boundary_edges")));
    EXPECT_EQ(t.nonmanifold_edges, std::stoi(row.at("nonmanifold_edges")));
    EXPECT_EQ(t.nonmanifold_vertices, std::stoi(row.at("nonmanifold_vertices")));
    EXPECT_EQ(t.closed, row.at("closed") == "True");
    EXPECT_EQ(t.oriented, row.at("consistently_oriented") == "True");
    EXPECT_EQ(t.faces, std::stoi(row.at("F")));
    EXPECT_GT(t.volume, 0.0);  // outward
  }
}

}  // namespace
}  // namespace arcs
