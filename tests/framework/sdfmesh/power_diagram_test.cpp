#include "framework/sdfmesh/power_diagram.h"

#include "framework/error.h"
#include "framework/spatial/topology.h"
#include "framework/util/parallel.h"
#include "framework/util/rng.h"
#include "tests/framework/sdfmesh/sdfmesh_test_fields.h"

#include <gtest/gtest.h>

#include <cmath>

namespace arcs {
namespace {

using testing::GridSamples;
using testing::SphereSdf;
using testing::TorusSdf;

#define REQUIRE_CGAL() \
  if (!PowerDiagramAvailable()) GTEST_SKIP() << "built without CGAL (libcgal-dev)"

double MaxRadiusError(const Mesh& m, double r) {
  double e = 0;
  for (int v = 0; v < m.NumVertices(); ++v) e = std::max(e, std::abs(m.V.row(v).norm() - r));
  return e;
}

TEST(PowerDiagramTest, SphereOnAGridIsAClosedOutwardManifold) {
  REQUIRE_CGAL();
  const SdfSamples s = GridSamples(16, -1, 1, [](const Vec3& p) { return SphereSdf(p, 0.6); });
  PowerDiagramStats st;
  const Mesh m = PowerDiagramContour(s, {}, &st);
  const Topology t = ComputeTopology(m);
  EXPECT_TRUE(t.closed);
  EXPECT_TRUE(t.manifold);
  EXPECT_TRUE(t.oriented);
  EXPECT_EQ(t.genus, 0);
  EXPECT_GT(t.volume, 0.0);
  EXPECT_LT(MaxRadiusError(m, 0.6), 0.125);  // within one cell (h = 0.125)
  EXPECT_GT(st.hidden, 0) << "the s^2 weights hide samples far from the surface";
  EXPECT_GT(st.crossed, 0);
}

TEST(PowerDiagramTest, ScatteredSamplesAndTheTorusGenus) {
  REQUIRE_CGAL();
  SdfSamples s;
  const int n = 20000;
  s.points.resize(n, 3);
  s.values.resize(n);
  Rng rng(3);
  for (int i = 0; i < n; ++i) {
    const Vec3 p(rng.Uniform(-1, 1), rng.Uniform(-1, 1), rng.Uniform(-1, 1));
    s.points.row(i) = p.transpose();
    s.values[i] = TorusSdf(p, 0.5, 0.22);
  }
  const Topology t = ComputeTopology(PowerDiagramContour(s));
  EXPECT_TRUE(t.closed);
  EXPECT_TRUE(t.manifold);
  EXPECT_EQ(t.genus, 1);
  EXPECT_GT(t.volume, 0.0);
}

TEST(PowerDiagramTest, UnweightedAndSphereGapVariants) {
  REQUIRE_CGAL();
  const SdfSamples s = GridSamples(12, -1, 1, [](const Vec3& p) { return SphereSdf(p, 0.55); });
  PowerDiagramOptions o;
  o.weighted = false;
  PowerDiagramStats st;
  const Topology t = ComputeTopology(PowerDiagramContour(s, o, &st));
  EXPECT_TRUE(t.closed);
  EXPECT_EQ(t.genus, 0);
  o.weighted = true;
  o.vertex = PowerDiagramOptions::Vertex::kSphereGap;
  const Mesh m = PowerDiagramContour(s, o);
  EXPECT_TRUE(ComputeTopology(m).closed);
  EXPECT_LT(MaxRadiusError(m, 0.55), 0.17);
}

TEST(PowerDiagramTest, SameMeshAtOneAndTwoThreads) {
  REQUIRE_CGAL();
  const SdfSamples s = GridSamples(14, -1, 1, [](const Vec3& p) { return TorusSdf(p, 0.45, 0.2); });
  Mesh a, b;
  {
    ThreadLimit l(1);
    a = PowerDiagramContour(s);
  }
  {
    ThreadLimit l(2);
    b = PowerDiagramContour(s);
  }
  EXPECT_EQ(a.V, b.V);
  EXPECT_EQ(a.F, b.F);
}

TEST(PowerDiagramTest, BadInputIsAClearError) {
  REQUIRE_CGAL();
  const SdfSamples good = GridSamples(4, -1, 1, [](const Vec3& p) { return SphereSdf(p, 0.5); });
  SdfSamples s = good;
  s.values.setConstant(-0.2);
  EXPECT_THROW(PowerDiagramContour(s), Error);
  s = good;
  s.values[0] = NAN;
  EXPECT_THROW(PowerDiagramContour(s), Error);
  s = good;
  s.values.conservativeResize(10);
  EXPECT_THROW(PowerDiagramContour(s), Error);
  // Coplanar samples span no volume.
  s = SdfSamples{};
  s.points = MatrixXd::Zero(4, 3);
  s.points.col(0) << 0, 1, 0, 1;
  s.points.col(1) << 0, 0, 1, 1;
  s.values = VectorXd(4);
  s.values << -0.1, 0.1, 0.1, 0.1;
  EXPECT_THROW(PowerDiagramContour(s), Error);
}

}  // namespace
}  // namespace arcs
