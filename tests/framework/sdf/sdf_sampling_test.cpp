#include "framework/sdf/sdf_sampling.h"

#include "framework/error.h"
#include "framework/geometry/builtin_shapes.h"
#include "framework/util/parallel.h"

#include <gtest/gtest.h>

#include <cmath>

namespace arcs {
namespace {

// Icosphere r = 0.5 with 4 subdivisions: the polyhedron lies within about
// 0.0015 of the sphere (inscribed; largest gap at face centres).
constexpr double kR = 0.5;
constexpr double kMeshTol = 0.002;

const Mesh& Sphere() {
  static const Mesh m = MakeIcosphere(kR, 4);
  return m;
}

TEST(SdfSamplingTest, GridOrderAndValuesMatchAnalyticSphere) {
  SdfGridOptions o;
  o.n = 20;
  const SdfSamples s = SampleSdfGrid(Sphere(), o, Context(1));
  ASSERT_TRUE(s.grid.has_value());
  EXPECT_EQ(s.grid->dims[0], 21);
  EXPECT_EQ(s.grid->dims[2], 21);
  EXPECT_EQ(s.grid->min[1], -1.0);
  EXPECT_EQ(s.grid->max[1], 1.0);
  ASSERT_EQ(s.Size(), 21 * 21 * 21);
  ASSERT_EQ(s.points.rows(), s.Size());
  ASSERT_EQ(s.points.cols(), 3);
  EXPECT_EQ(s.dim, 3);
  EXPECT_EQ(s.clamp, 0.0);
  int negative = 0;
  for (int k = 0; k < 21; ++k) {
    for (int j = 0; j < 21; ++j) {
      for (int i = 0; i < 21; ++i) {
        const int idx = i + 21 * (j + 21 * k);
        ASSERT_NEAR(s.points(idx, 0), -1.0 + 0.1 * i, 1e-14);
        ASSERT_NEAR(s.points(idx, 1), -1.0 + 0.1 * j, 1e-14);
        ASSERT_NEAR(s.points(idx, 2), -1.0 + 0.1 * k, 1e-14);
        const double exact = s.points.row(idx).norm() - kR;
        ASSERT_NEAR(s.values[idx], exact, kMeshTol) << "node " << i << "," << j << "," << k;
        if (std::abs(exact) > kMeshTol) {
          ASSERT_EQ(s.values[idx] < 0, exact < 0);
        }
        negative += s.values[idx] < 0;
      }
    }
  }
  // 485 nodes lie strictly inside the sphere (i^2 + j^2 + k^2 < 25); the 30
  // nodes exactly on it are outside the inscribed polyhedron (or on it: +).
  EXPECT_EQ(negative, 485);
  EXPECT_EQ(s.points(21 * 21 * 21 - 1, 0), 1.0);  // linspace ends exactly at hi
}

TEST(SdfSamplingTest, FastAndExactSignsAgreeAndThreadIndependent) {
  SdfGridOptions o;
  o.n = 16;
  o.lo = -0.7;
  o.hi = 0.8;
  SdfSamples fast1, fast2;
  {
    ThreadLimit limit(1);
    fast1 = SampleSdfGrid(Sphere(), o, Context(1));
  }
  {
    ThreadLimit limit(2);
    fast2 = SampleSdfGrid(Sphere(), o, Context(1));
  }
  EXPECT_TRUE(fast1.values == fast2.values);
  o.sign = SdfGridOptions::Sign::kExactWindingNumber;
  const SdfSamples exact = SampleSdfGrid(Sphere(), o, Context(1));
  EXPECT_TRUE(exact.values == fast1.values);
}

TEST(SdfSamplingTest, SignedDistanceOfPoints) {
  MatrixX3d P(4, 3);
  P << 0, 0, 0, 0.2, 0.1, 0, 1, 0, 0, 0, -0.9, 0.3;
  const VectorXd s = SignedDistance(Sphere(), P);
  ASSERT_EQ(s.size(), 4);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(s[i], P.row(i).norm() - kR, kMeshTol);
  EXPECT_LT(s[0], 0.0);
  EXPECT_GT(s[2], 0.0);
  EXPECT_THROW(SignedDistance(Mesh{}, P), Error);
}

TEST(SdfSamplingTest, RandomSamplesInBoxSeededByContext) {
  const SdfSamples a = SampleSdfRandom(Sphere(), 5000, -0.8, 0.6, Context(3));
  const SdfSamples b = SampleSdfRandom(Sphere(), 5000, -0.8, 0.6, Context(3));
  const SdfSamples c = SampleSdfRandom(Sphere(), 5000, -0.8, 0.6, Context(4));
  ASSERT_EQ(a.Size(), 5000);
  EXPECT_FALSE(a.grid.has_value());
  EXPECT_TRUE(a.points == b.points);
  EXPECT_TRUE(a.values == b.values);
  EXPECT_FALSE(a.points == c.points);
  EXPECT_GE(a.points.minCoeff(), -0.8);
  EXPECT_LT(a.points.maxCoeff(), 0.6);
  EXPECT_GT(a.points.minCoeff(), -0.81 + 0.005);  // actually spread over the box
  EXPECT_GT(a.points.maxCoeff(), 0.59);
  for (int i = 0; i < a.Size(); ++i) {
    ASSERT_NEAR(a.values[i], a.points.row(i).norm() - kR, kMeshTol);
  }
  // Fraction of points inside ~ sphere volume / box volume.
  const double frac = (a.values.array() < 0).cast<double>().mean();
  EXPECT_NEAR(frac, 4.0 / 3.0 * M_PI * 0.125 / (1.4 * 1.4 * 1.4), 0.02);
}

TEST(SdfSamplingTest, NoiseAndClamp) {
  SdfSamples s;
  s.points = MatrixXd::Zero(100000, 3);
  s.values = VectorXd::Zero(100000);
  AddGaussianNoise(&s, 0.01, 7);
  const double mean = s.values.mean();
  const double sd = std::sqrt((s.values.array() - mean).square().mean());
  EXPECT_NEAR(mean, 0.0, 1e-4);
  EXPECT_NEAR(sd, 0.01, 1e-4);
  SdfSamples t;
  t.points = MatrixXd::Zero(100000, 3);
  t.values = VectorXd::Zero(100000);
  {
    ThreadLimit limit(1);
    AddGaussianNoise(&t, 0.01, 7);
  }
  EXPECT_TRUE(s.values == t.values);
  ClampSdf(&s, 0.015);
  EXPECT_EQ(s.clamp, 0.015);
  EXPECT_LE(s.values.cwiseAbs().maxCoeff(), 0.015);
  EXPECT_GT((s.values.array() == 0.015).count(), 5000);  // ~6.7% above 1.5 sigma
  EXPECT_THROW(ClampSdf(&s, 0.0), OptionError);
  EXPECT_THROW(AddGaussianNoise(&s, -1.0, 1), OptionError);
}

TEST(SdfSamplingTest, OptionsAreChecked) {
  SdfGridOptions o;
  o.n = 0;
  EXPECT_THROW(o.Check(), OptionError);
  o.n = 10;
  o.hi = -2;
  EXPECT_THROW(o.Check(), OptionError);
  EXPECT_THROW(SampleSdfGrid(Sphere(), o, Context(1)), OptionError);
  EXPECT_THROW(SampleSdfGrid(Mesh{}, SdfGridOptions{}, Context(1)), Error);
}

}  // namespace
}  // namespace arcs
