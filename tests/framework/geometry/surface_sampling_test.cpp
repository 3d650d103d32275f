#include "framework/geometry/surface_sampling.h"

#include "framework/error.h"
#include "framework/util/parallel.h"

#include <gtest/gtest.h>

#include <cmath>

namespace arcs {
namespace {

// Two triangles in the plane z = 0.5 with areas 1 and 3.
Mesh TwoTriangles() {
  Mesh m;
  m.V.resize(5, 3);
  m.V << 0, 0, 0.5,   //
      2, 0, 0.5,      //
      0, 1, 0.5,      // triangle 0: (0,0),(2,0),(0,1): area 1
      -3, 0, 0.5,     //
      0, -2, 0.5;     // triangle 1: (0,0),(-3,0),(0,-2): area 3
  m.F.resize(2, 3);
  m.F << 0, 1, 2, 0, 4, 3;
  return m;
}

TEST(SurfaceSamplingTest, CountOnSurfaceAndAreaUniform) {
  const Mesh m = TwoTriangles();
  const int n = 200000;
  Eigen::VectorXi faces;
  const MatrixX3d P = SampleSurfaceUniform(m, n, 5, &faces);
  ASSERT_EQ(P.rows(), n);
  ASSERT_EQ(faces.size(), n);
  int in_first = 0;
  Vec3 mean0 = Vec3::Zero();
  for (int i = 0; i < n; ++i) {
    const double x = P(i, 0), y = P(i, 1);
    ASSERT_NEAR(P(i, 2), 0.5, 1e-15);
    if (faces[i] == 0) {
      // Inside triangle 0: x >= 0, y >= 0, x/2 + y <= 1.
      ASSERT_GE(x, 0.0);
      ASSERT_GE(y, 0.0);
      ASSERT_LE(x / 2 + y, 1.0 + 1e-12);
      ++in_first;
      mean0 += P.row(i).transpose();
    } else {
      ASSERT_EQ(faces[i], 1);
      ASSERT_LE(x, 0.0);
      ASSERT_LE(y, 0.0);
      ASSERT_LE(-x / 3 - y / 2, 1.0 + 1e-12);
    }
  }
  // Fraction on the area-1 triangle: 1/4, binomial sd ~ 0.001.
  EXPECT_NEAR(static_cast<double>(in_first) / n, 0.25, 0.005);
  // Uniform inside the triangle: the mean is the centroid (2/3, 1/3).
  mean0 /= in_first;
  EXPECT_NEAR(mean0.x(), 2.0 / 3.0, 0.01);
  EXPECT_NEAR(mean0.y(), 1.0 / 3.0, 0.01);
}

TEST(SurfaceSamplingTest, SameAtOneAndTwoThreadsAndSeedMatters) {
  const Mesh m = TwoTriangles();
  MatrixX3d a, b;
  {
    ThreadLimit limit(1);
    a = SampleSurfaceUniform(m, 50000, 9);
  }
  {
    ThreadLimit limit(2);
    b = SampleSurfaceUniform(m, 50000, 9);
  }
  EXPECT_TRUE(a == b);
  const MatrixX3d c = SampleSurfaceUniform(m, 50000, 10);
  EXPECT_FALSE(a == c);
  // A prefix of a longer run is the shorter run (per-index streams).
  const MatrixX3d d = SampleSurfaceUniform(m, 1000, 9);
  EXPECT_TRUE(d == a.topRows(1000));
}

TEST(SurfaceSamplingTest, ZeroAreaFacesNeverSampledAndErrors) {
  Mesh m = TwoTriangles();
  m.F.conservativeResize(3, 3);
  m.F.row(2) << 0, 1, 1;  // degenerate
  Eigen::VectorXi faces;
  SampleSurfaceUniform(m, 10000, 1, &faces);
  EXPECT_EQ((faces.array() == 2).count(), 0);
  EXPECT_THROW(SampleSurfaceUniform(Mesh{}, 10, 1), Error);
  Mesh flat = m;
  flat.F.resize(1, 3);
  flat.F << 0, 1, 1;
  EXPECT_THROW(SampleSurfaceUniform(flat, 10, 1), Error);
  EXPECT_THROW(SampleSurfaceUniform(m, -1, 1), Error);
  EXPECT_EQ(SampleSurfaceUniform(m, 0, 1).rows(), 0);
}

}  // namespace
}  // namespace arcs
