// The exact 2D SDF of polylines (grid protocol and random samples).
#include "framework/geometry/curves.h"
#include "framework/sdf/sdf2d.h"

#include <gtest/gtest.h>

#include <cmath>

namespace arcs {
namespace {

TEST(Sdf2D, ExactOnACircleWithTheGridLayout) {
  const Polyline c = MakeBuiltinCurve("circle", 4096);  // chord error 0.5 (1 - cos(pi/4096)) < 1.5e-7
  SdfGrid2DOptions o;
  o.n = 20;
  const SdfSamples s = SampleSdfGrid2D(c, o, Context(1));
  ASSERT_EQ(s.dim, 2);
  ASSERT_TRUE(s.grid.has_value());
  EXPECT_EQ(s.grid->dim, 2);
  EXPECT_EQ(s.grid->dims[0], 21);
  EXPECT_EQ(s.grid->dims[1], 21);
  EXPECT_EQ(s.grid->dims[2], 1);
  ASSERT_EQ(s.Size(), 21 * 21);
  ASSERT_EQ(s.points.cols(), 2);
  for (int j = 0; j <= 20; ++j)
    for (int i = 0; i <= 20; ++i) {
      const int idx = i + 21 * j;
      EXPECT_DOUBLE_EQ(s.points(idx, 0), -1.0 + 0.1 * i) << idx;
      EXPECT_DOUBLE_EQ(s.points(idx, 1), -1.0 + 0.1 * j) << idx;
      const double exact = s.points.row(idx).norm() - 0.5;
      EXPECT_NEAR(s.values[idx], exact, 2e-7) << "at " << s.points.row(idx);
    }
  // The annulus: negative only between the circles.
  const VectorXd v = SignedDistance2D(MakeBuiltinCurve("annulus", 4096), (MatrixXd(3, 2) << 0, 0, 0.375, 0, 0.7, 0).finished());
  EXPECT_NEAR(v[0], 0.25, 1e-6);
  EXPECT_NEAR(v[1], -0.125, 1e-6);
  EXPECT_NEAR(v[2], 0.2, 1e-6);
}

TEST(Sdf2D, RandomSamplesAreSeededAndExact) {
  const Polyline c = MakeBuiltinCurve("circle", 4096);
  const SdfSamples a = SampleSdfRandom2D(c, 500, -1, 1, Context(4));
  const SdfSamples b = SampleSdfRandom2D(c, 500, -1, 1, Context(4));
  EXPECT_EQ((a.points - b.points).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_FALSE(a.grid.has_value());
  for (int i = 0; i < 500; ++i) EXPECT_NEAR(a.values[i], a.points.row(i).norm() - 0.5, 2e-7);
  EXPECT_THROW(SampleSdfRandom2D(c, 0, -1, 1, Context(1)), OptionError);
  Polyline bad = c;
  bad.V(3, 1) = std::nan("");
  EXPECT_THROW(SampleSdfGrid2D(bad, SdfGrid2DOptions{}, Context(1)), InputError);
}

}  // namespace
}  // namespace arcs
