#include "framework/geometry/marching_cubes.h"

#include "framework/error.h"

#include "framework/spatial/topology.h"
#include "framework/util/parallel.h"
#include "framework/util/rng.h"

#include <Eigen/Geometry>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <numbers>
#include <numeric>
#include <set>
#include <utility>
#include <vector>

namespace arcs {
namespace {

// An independent check of the output's combinatorics (not relying on
// ComputeTopology): every directed edge occurs once and its reverse once
// (closed, edge-manifold, consistently oriented), every vertex's link is one
// cycle (vertex-manifold), and the genus from the Euler characteristic.
struct Check {
  bool closed_oriented = true;
  bool vertex_manifold = true;
  int components = 0;
  int genus = -1;
  double volume = 0.0;
};

Check CheckMesh(const Mesh& m) {
  Check c;
  std::map<std::pair<int, int>, int> directed;
  for (int f = 0; f < m.NumFaces(); ++f) {
    for (int k = 0; k < 3; ++k) ++directed[{m.F(f, k), m.F(f, (k + 1) % 3)}];
  }
  for (const auto& [e, n] : directed) {
    if (n != 1 || !directed.count({e.second, e.first})) c.closed_oriented = false;
  }
  // Vertex links: for face (v, a, b), the link of v has the directed edge a -> b.
  std::vector<std::map<int, int>> link(m.NumVertices());
  for (int f = 0; f < m.NumFaces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      auto& l = link[m.F(f, k)];
      const int a = m.F(f, (k + 1) % 3), b = m.F(f, (k + 2) % 3);
      if (l.count(a)) c.vertex_manifold = false;
      l[a] = b;
    }
  }
  for (const auto& l : link) {
    if (l.empty()) continue;
    int steps = 0, x = l.begin()->first;
    do {
      auto it = l.find(x);
      if (it == l.end()) {
        c.vertex_manifold = false;
        break;
      }
      x = it->second;
      ++steps;
    } while (x != l.begin()->first && steps <= static_cast<int>(l.size()));
    if (steps != static_cast<int>(l.size())) c.vertex_manifold = false;
  }
  // Components (union-find over face vertices) and Euler characteristic.
  std::vector<int> parent(m.NumVertices());
  std::iota(parent.begin(), parent.end(), 0);
  std::function<int(int)> find = [&](int x) { return parent[x] == x ? x : parent[x] = find(parent[x]); };
  std::set<int> used;
  for (int f = 0; f < m.NumFaces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      used.insert(m.F(f, k));
      parent[find(m.F(f, k))] = find(m.F(f, (k + 1) % 3));
    }
  }
  std::set<int> roots;
  for (int v : used) roots.insert(find(v));
  c.components = static_cast<int>(roots.size());
  const int euler = static_cast<int>(used.size()) - static_cast<int>(directed.size() / 2) + m.NumFaces();
  if (c.closed_oriented && c.vertex_manifold) c.genus = (2 * c.components - euler) / 2;
  for (int f = 0; f < m.NumFaces(); ++f) {
    const Vec3 a = m.V.row(m.F(f, 0)), b = m.V.row(m.F(f, 1)), d = m.V.row(m.F(f, 2));
    c.volume += a.dot(b.cross(d)) / 6.0;
  }
  return c;
}

GridInfo CubeGrid(int nodes, double lo, double hi) {
  GridInfo g;
  g.dim = 3;
  g.dims = {nodes, nodes, nodes};
  g.min = {lo, lo, lo};
  g.max = {hi, hi, hi};
  return g;
}

VectorXd Sample(const GridInfo& g, const std::function<double(const Vec3&)>& f) {
  VectorXd v(g.NumNodes());
  for (int k = 0; k < g.dims[2]; ++k) {
    for (int j = 0; j < g.dims[1]; ++j) {
      for (int i = 0; i < g.dims[0]; ++i) {
        const Vec3 p(g.min[0] + i * g.Spacing(0), g.min[1] + j * g.Spacing(1),
                     g.min[2] + k * g.Spacing(2));
        v[i + g.dims[0] * (j + g.dims[1] * k)] = f(p);
      }
    }
  }
  return v;
}

TEST(MarchingCubesTest, TableIsDerivedConsistently) {
  EXPECT_TRUE(detail::MarchingCubesCase(0).empty());
  EXPECT_TRUE(detail::MarchingCubesCase(255).empty());
  for (int c = 0; c < 8; ++c) {
    EXPECT_EQ(detail::MarchingCubesCase(1 << c).size(), 1u);          // one corner in: a triangle
    EXPECT_EQ(detail::MarchingCubesCase(255 ^ (1 << c)).size(), 1u);  // one corner out
  }
  // Two adjacent inside corners (an edge): a quad, two triangles.
  EXPECT_EQ(detail::MarchingCubesCase(0b11).size(), 2u);
  // Two diagonally opposite inside corners (0 and 7): separated, two triangles.
  EXPECT_EQ(detail::MarchingCubesCase(0b10000001).size(), 2u);
  // Every crossed cube edge is used by the case's triangles, no other edge.
  for (int config = 1; config < 255; ++config) {
    std::set<int> used;
    for (const auto& t : detail::MarchingCubesCase(config)) used.insert(t.begin(), t.end());
    for (int e = 0; e < 12; ++e) {
      const int c0 = detail::MarchingCubesEdgeCorner(e), c1 = c0 | (1 << (e / 4));
      const bool crossed = ((config >> c0) & 1) != ((config >> c1) & 1);
      EXPECT_EQ(used.count(e) == 1, crossed) << "config " << config << " edge " << e;
    }
  }
}

TEST(MarchingCubesTest, SingleInsideNodeGivesOutwardOctahedron) {
  GridInfo g = CubeGrid(3, -1.0, 1.0);  // spacing 1
  VectorXd v = VectorXd::Ones(27);
  v[13] = -1.0;  // centre node
  const Mesh m = MarchingCubes(v, g);
  EXPECT_EQ(m.NumVertices(), 6);
  EXPECT_EQ(m.NumFaces(), 8);
  const Check c = CheckMesh(m);
  EXPECT_TRUE(c.closed_oriented);
  EXPECT_EQ(c.genus, 0);
  EXPECT_NEAR(c.volume, 4.0 / 3.0 * 0.125, 1e-12);  // vertices at the edge midpoints
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(m.V.row(i).norm(), 0.5, 1e-12);
}

TEST(MarchingCubesTest, SphereIsClosedGenusZeroAccurate) {
  const double r = 0.5;
  const GridInfo g = CubeGrid(41, -1.0, 1.0);  // n = 40, h = 0.05
  const VectorXd v = Sample(g, [&](const Vec3& p) { return p.norm() - r; });
  const Mesh m = MarchingCubes(v, g);
  ASSERT_GT(m.NumFaces(), 1000);
  const Check c = CheckMesh(m);
  EXPECT_TRUE(c.closed_oriented);
  EXPECT_TRUE(c.vertex_manifold);
  EXPECT_EQ(c.components, 1);
  EXPECT_EQ(c.genus, 0);
  const double exact = 4.0 / 3.0 * std::numbers::pi * r * r * r;
  EXPECT_GT(c.volume, 0.0);
  EXPECT_NEAR(c.volume / exact, 1.0, 0.02);
  const double h = 0.05;
  double worst = 0.0;
  for (int i = 0; i < m.NumVertices(); ++i) worst = std::max(worst, std::abs(m.V.row(i).norm() - r));
  // Linear interpolation of the exact SDF along an edge: error O(h^2 / r).
  EXPECT_LT(worst, 0.05 * h);
  // Cross-check with the spatial module's topology.
  const Topology t = ComputeTopology(m);
  EXPECT_TRUE(t.closed);
  EXPECT_TRUE(t.manifold);
  EXPECT_TRUE(t.oriented);
  EXPECT_EQ(t.genus, 0);
  EXPECT_GT(t.volume, 0.0);
}

TEST(MarchingCubesTest, TorusHasGenusOne) {
  const double R = 0.5, r = 0.2;
  const GridInfo g = CubeGrid(41, -1.0, 1.0);
  const VectorXd v = Sample(g, [&](const Vec3& p) {
    const double q = std::hypot(p.x(), p.y()) - R;
    return std::hypot(q, p.z()) - r;
  });
  const Mesh m = MarchingCubes(v, g);
  const Check c = CheckMesh(m);
  EXPECT_TRUE(c.closed_oriented);
  EXPECT_TRUE(c.vertex_manifold);
  EXPECT_EQ(c.components, 1);
  EXPECT_EQ(c.genus, 1);
  const double exact = 2.0 * std::numbers::pi * std::numbers::pi * R * r * r;
  EXPECT_NEAR(c.volume / exact, 1.0, 0.03);
}

TEST(MarchingCubesTest, NonCubicGridAndIsovalue) {
  // Anisotropic box grid; level set |p| = 0.6 of f = |p| via the isovalue.
  GridInfo g;
  g.dim = 3;
  g.dims = {31, 25, 41};
  g.min = {-1.0, -0.9, -1.2};
  g.max = {1.0, 0.8, 1.0};
  const VectorXd v = Sample(g, [](const Vec3& p) { return p.norm(); });
  const Mesh m = MarchingCubes(v, g, 0.6);
  const Check c = CheckMesh(m);
  EXPECT_TRUE(c.closed_oriented);
  EXPECT_EQ(c.genus, 0);
  EXPECT_NEAR(c.volume / (4.0 / 3.0 * std::numbers::pi * 0.216), 1.0, 0.03);
  for (int i = 0; i < m.NumVertices(); ++i) EXPECT_NEAR(m.V.row(i).norm(), 0.6, 0.01);
}

// The real test of the derived table: arbitrary sign patterns, padded with an
// outside layer so the surface cannot reach the grid boundary, must always
// give closed, manifold, oriented meshes enclosing positive volume.
TEST(MarchingCubesTest, RandomGridsAlwaysClosedManifoldOriented) {
  Rng rng(2024);
  for (int trial = 0; trial < 300; ++trial) {
    GridInfo g;
    g.dim = 3;
    for (int a = 0; a < 3; ++a) {
      g.dims[a] = 3 + static_cast<int>(rng.UniformInt(5));
      g.min[a] = -1.0;
      g.max[a] = 1.0 + a;
    }
    const int mode = trial % 3;  // 0: values +-1; 1: random reals; 2: reals with exact zeros
    VectorXd v(g.NumNodes());
    int inside = 0;
    for (int k = 0; k < g.dims[2]; ++k) {
      for (int j = 0; j < g.dims[1]; ++j) {
        for (int i = 0; i < g.dims[0]; ++i) {
          const bool border = i == 0 || j == 0 || k == 0 || i == g.dims[0] - 1 ||
                              j == g.dims[1] - 1 || k == g.dims[2] - 1;
          double x;
          if (mode == 0) {
            x = rng.Uniform() < 0.5 ? -1.0 : 1.0;
          } else {
            x = rng.Uniform(-1.0, 1.0);
            if (mode == 2 && rng.Uniform() < 0.2) x = 0.0;
          }
          if (border) x = std::abs(x) + 0.5;
          inside += x < 0.0;
          v[i + g.dims[0] * (j + g.dims[1] * k)] = x;
        }
      }
    }
    const Mesh m = MarchingCubes(v, g);
    const Check c = CheckMesh(m);
    ASSERT_TRUE(c.closed_oriented) << "trial " << trial;
    ASSERT_TRUE(c.vertex_manifold) << "trial " << trial;
    ASSERT_GE(c.genus, 0) << "trial " << trial;
    if (inside > 0 && mode != 2) {
      ASSERT_GT(c.volume, 0.0) << "trial " << trial;
    }
    if (inside == 0) {
      ASSERT_EQ(m.NumFaces(), 0);
    }
  }
}

TEST(MarchingCubesTest, DeterministicAcrossThreadCounts) {
  const GridInfo g = CubeGrid(33, -1.0, 1.0);
  const VectorXd v = Sample(g, [](const Vec3& p) {
    return std::min(Vec3(p.x() - 0.3, p.y(), p.z()).norm() - 0.35, (p + Vec3(0.3, 0.1, 0)).norm() - 0.3);
  });
  Mesh a, b;
  {
    ThreadLimit limit(1);
    a = MarchingCubes(v, g);
  }
  {
    ThreadLimit limit(2);
    b = MarchingCubes(v, g);
  }
  ASSERT_GT(a.NumFaces(), 0);
  EXPECT_TRUE(a.V == b.V);
  EXPECT_TRUE(a.F == b.F);
}

TEST(MarchingCubesTest, SurfaceOpenAtGridBoundaryAndBadInput) {
  const GridInfo g = CubeGrid(11, -1.0, 1.0);
  const VectorXd v = Sample(g, [](const Vec3& p) { return p.z() - 0.05; });  // a plane
  const Mesh m = MarchingCubes(v, g);
  EXPECT_EQ(m.NumFaces(), 2 * 10 * 10);
  EXPECT_FALSE(CheckMesh(m).closed_oriented);
  // Normals point to +z (the positive side).
  for (int f = 0; f < m.NumFaces(); ++f) {
    const Vec3 a = m.V.row(m.F(f, 0)), b = m.V.row(m.F(f, 1)), c = m.V.row(m.F(f, 2));
    EXPECT_GT((b - a).cross(c - a).z(), 0.0);
  }
  EXPECT_THROW(MarchingCubes(VectorXd::Zero(5), g), Error);
  VectorXd bad = v;
  bad[3] = std::nan("");
  EXPECT_THROW(MarchingCubes(bad, g), Error);
  GridInfo flat = g;
  flat.dim = 2;
  EXPECT_THROW(MarchingCubes(v, flat), Error);
}

// ---- marching squares ------------------------------------------------------

GridInfo SquareGrid(int nodes, double lo, double hi) {
  GridInfo g;
  g.dim = 2;
  g.dims = {nodes, nodes, 1};
  g.min = {lo, lo, 0.0};
  g.max = {hi, hi, 0.0};
  return g;
}

VectorXd Sample2(const GridInfo& g, const std::function<double(double, double)>& f) {
  VectorXd v(static_cast<Eigen::Index>(g.dims[0]) * g.dims[1]);
  for (int j = 0; j < g.dims[1]; ++j) {
    for (int i = 0; i < g.dims[0]; ++i) {
      v[i + g.dims[0] * j] = f(g.min[0] + i * g.Spacing(0), g.min[1] + j * g.Spacing(1));
    }
  }
  return v;
}

// Closed loops (each vertex: one edge in, one out); returns signed areas.
std::vector<double> LoopAreas(const Polyline2& pl) {
  std::vector<int> next(pl.V.rows(), -1), indeg(pl.V.rows(), 0);
  for (int e = 0; e < pl.E.rows(); ++e) {
    EXPECT_EQ(next[pl.E(e, 0)], -1);
    next[pl.E(e, 0)] = pl.E(e, 1);
    ++indeg[pl.E(e, 1)];
  }
  std::vector<bool> seen(pl.V.rows(), false);
  std::vector<double> areas;
  for (int s = 0; s < pl.V.rows(); ++s) {
    EXPECT_EQ(indeg[s], 1);
    EXPECT_NE(next[s], -1);
    if (seen[s] || next[s] < 0) continue;
    double a = 0.0;
    for (int x = s; !seen[x]; x = next[x]) {
      seen[x] = true;
      const int y = next[x];
      a += 0.5 * (pl.V(x, 0) * pl.V(y, 1) - pl.V(y, 0) * pl.V(x, 1));
    }
    areas.push_back(a);
  }
  return areas;
}

TEST(MarchingSquaresTest, CircleIsOneCounterClockwiseLoop) {
  const GridInfo g = SquareGrid(41, -1.0, 1.0);
  const double r = 0.5;
  const Polyline2 pl = MarchingSquares(Sample2(g, [&](double x, double y) { return std::hypot(x, y) - r; }), g);
  ASSERT_EQ(pl.V.cols(), 2);
  const std::vector<double> areas = LoopAreas(pl);
  ASSERT_EQ(areas.size(), 1u);
  EXPECT_GT(areas[0], 0.0);
  EXPECT_NEAR(areas[0] / (std::numbers::pi * r * r), 1.0, 0.01);
  for (int i = 0; i < pl.V.rows(); ++i) EXPECT_NEAR(pl.V.row(i).norm(), r, 0.003);
}

TEST(MarchingSquaresTest, AnnulusHasOuterCcwAndInnerCw) {
  const GridInfo g = SquareGrid(61, -1.0, 1.0);
  const Polyline2 pl = MarchingSquares(Sample2(g, [](double x, double y) {
    const double d = std::hypot(x, y);
    return std::max(d - 0.6, 0.3 - d);
  }), g);
  std::vector<double> areas = LoopAreas(pl);
  ASSERT_EQ(areas.size(), 2u);
  std::sort(areas.begin(), areas.end());
  EXPECT_NEAR(areas[0], -std::numbers::pi * 0.09, 0.01 * std::numbers::pi * 0.09);
  EXPECT_NEAR(areas[1], std::numbers::pi * 0.36, 0.01 * std::numbers::pi * 0.36);
}

TEST(MarchingSquaresTest, RandomGridsGiveClosedLoops) {
  Rng rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 3 + static_cast<int>(rng.UniformInt(8));
    const GridInfo g = SquareGrid(n, 0.0, 1.0);
    int inside = 0;
    const Polyline2 pl = MarchingSquares(Sample2(g, [&](double x, double y) {
      const bool border = x == 0.0 || y == 0.0 || x == 1.0 || y == 1.0;
      double v = trial % 2 ? (rng.Uniform() < 0.5 ? -1.0 : 1.0) : rng.Uniform(-1.0, 1.0);
      if (border) v = std::abs(v) + 0.1;
      inside += v < 0;
      return v;
    }), g);
    const std::vector<double> areas = LoopAreas(pl);
    double total = 0.0;
    for (double a : areas) total += a;
    if (inside > 0) {
      ASSERT_GT(total, 0.0) << "trial " << trial;
    } else {
      ASSERT_EQ(pl.E.rows(), 0);
    }
  }
}

}  // namespace
}  // namespace arcs
