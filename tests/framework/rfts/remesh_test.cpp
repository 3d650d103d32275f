// The Botsch–Kobbelt patch remesher of RFTS: edge lengths move toward the
// target, the mesh stays a closed oriented genus-0 manifold on the surface,
// and nothing outside the patch moves.
#include "framework/error.h"
#include "framework/geometry/builtin_shapes.h"
#include "framework/rfts/remesh.h"
#include "framework/spatial/topology.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>

namespace arcs {
namespace {

std::vector<double> EdgeLengths(const Mesh& m) {
  std::vector<double> l;
  for (int f = 0; f < m.NumFaces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = m.F(f, k), b = m.F(f, (k + 1) % 3);
      if (a < b) l.push_back((m.V.row(a) - m.V.row(b)).norm());
    }
  return l;
}

TEST(RftsRemesh, WholeMeshReachesTargetLengthAndStaysOnTheSphere) {
  Mesh m = MakeIcosphere(1.0, 2);  // edges about 0.3
  RemeshOptions o;
  o.target_edge_length = 0.1;
  o.iterations = 8;
  const RemeshStats st = RemeshPatch(&m, {}, o);
  EXPECT_GT(st.splits, 0);
  const Topology t = ComputeTopology(m);
  EXPECT_TRUE(t.closed && t.manifold && t.oriented) << t.nonmanifold_edges;
  EXPECT_EQ(t.genus, 0);
  EXPECT_GT(t.volume, 0);
  const auto l = EdgeLengths(m);
  int in_range = 0;
  for (double x : l) in_range += x > 0.7 * 0.1 * 0.9 && x < 1.4 * 0.1 * 1.05;
  EXPECT_GT(in_range, 0.9 * l.size()) << in_range << " of " << l.size();
  // Vertices are projected onto the input (a polyhedron inscribed in the unit sphere).
  for (int v = 0; v < m.NumVertices(); ++v) {
    const double r = m.V.row(v).norm();
    EXPECT_LE(r, 1.0 + 1e-9);
    EXPECT_GT(r, 0.95);
  }
}

TEST(RftsRemesh, CoarseningCollapsesAndKeepsGenus) {
  Mesh m = MakeIcosphere(1.0, 4);  // edges about 0.075
  RemeshOptions o;
  o.target_edge_length = 0.3;
  o.iterations = 10;
  const RemeshStats st = RemeshPatch(&m, {}, o);
  EXPECT_GT(st.collapses, 0);
  EXPECT_LT(m.NumFaces(), 1000);
  const Topology t = ComputeTopology(m);
  EXPECT_TRUE(t.closed && t.manifold && t.oriented);
  EXPECT_EQ(t.genus, 0);
}

TEST(RftsRemesh, OnlyThePatchChanges) {
  Mesh m = MakeIcosphere(1.0, 3);
  const Mesh before = m;
  std::vector<char> active(m.NumFaces(), 0);
  int n_active = 0;
  for (int f = 0; f < m.NumFaces(); ++f) {
    const Vec3 c = (m.V.row(m.F(f, 0)) + m.V.row(m.F(f, 1)) + m.V.row(m.F(f, 2))) / 3.0;
    if (c.z() > 0.5) active[f] = 1, ++n_active;
  }
  ASSERT_GT(n_active, 10);
  RemeshOptions o;
  o.target_edge_length = 0.05;
  RemeshPatch(&m, active, o);
  const Topology t = ComputeTopology(m);
  EXPECT_TRUE(t.closed && t.manifold && t.oriented);
  EXPECT_EQ(t.genus, 0);
  EXPECT_GT(m.NumFaces(), before.NumFaces());
  // Every inactive face of the input is still there, with the same corners.
  int found = 0, inactive = 0;
  for (int f = 0; f < before.NumFaces(); ++f) {
    if (active[f]) continue;
    ++inactive;
    for (int g = 0; g < m.NumFaces(); ++g) {
      bool same = true;
      for (int k = 0; k < 3; ++k) same = same && (m.V.row(m.F(g, k)) - before.V.row(before.F(f, k))).norm() == 0.0;
      if (same) {
        ++found;
        break;
      }
    }
  }
  EXPECT_EQ(found, inactive);
}

TEST(RftsRemesh, RejectsOpenMeshesAndBadOptions) {
  Mesh m = MakeIcosphere(1.0, 1);
  Mesh open = m;
  open.F.conservativeResize(m.NumFaces() - 1, 3);
  RemeshOptions o;
  EXPECT_THROW(RemeshPatch(&open, {}, o), InputError);
  o.target_edge_length = -1;
  EXPECT_THROW(RemeshPatch(&m, {}, o), OptionError);
  o.target_edge_length = 0.1;
  EXPECT_THROW(RemeshPatch(&m, std::vector<char>(3, 1), o), InputError);
}

}  // namespace
}  // namespace arcs
