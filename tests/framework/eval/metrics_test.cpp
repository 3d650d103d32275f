#include "framework/eval/metrics.h"

#include "framework/error.h"
#include "framework/geometry/builtin_shapes.h"
#include "framework/util/parallel.h"
#include "framework/util/rng.h"

#include <gtest/gtest.h>

#include <cmath>

namespace arcs {
namespace {

constexpr double kR = 0.5;

const Mesh& Sphere() {
  static const Mesh m = MakeIcosphere(kR, 4);  // within ~0.0015 of the sphere
  return m;
}

Mesh Scaled(const Mesh& m, double s) {
  Mesh out = m;
  out.V *= s;
  return out;
}

// Axis-aligned box [lo, hi]^3 as 12 outward triangles.
Mesh Box(double lo, double hi) {
  Mesh m;
  m.V.resize(8, 3);
  for (int c = 0; c < 8; ++c) {
    m.V.row(c) << ((c & 1) ? hi : lo), ((c & 2) ? hi : lo), ((c & 4) ? hi : lo);
  }
  m.F.resize(12, 3);
  m.F << 0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4, 2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6,
      2, 1, 3, 7, 1, 7, 5;
  return m;
}

TEST(MetricsTest, ChamferPaperSelfIsTheSamplingFloor) {
  const double c4 = ChamferPaper(Sphere(), Sphere(), 10000, 1);
  const double c5 = ChamferPaper(Sphere(), Sphere(), 100000, 1);
  EXPECT_GT(c5, 0.0);
  EXPECT_LT(c5, c4);
  // Nearest-sample distance ~ 1/sqrt(density): the floor falls like 1/sqrt(N).
  EXPECT_NEAR(c4 / c5, std::sqrt(10.0), 0.4);
  EXPECT_GT(c5, 0.003);
  EXPECT_LT(c5, 0.01);
  // Seeded: same seed same value, different seed a (slightly) different value.
  EXPECT_EQ(ChamferPaper(Sphere(), Sphere(), 10000, 1), c4);
  EXPECT_NE(ChamferPaper(Sphere(), Sphere(), 10000, 2), c4);
}

TEST(MetricsTest, ChamferOfConcentricSpheres) {
  const Mesh big = Scaled(Sphere(), 1.1);
  // Every point of one sphere is 0.1 r from the other: RMS 0.05 each way.
  const double p2s = ChamferPointToSurface(Sphere(), big, 100000, 3);
  EXPECT_NEAR(p2s, 2 * 0.1 * kR, 0.003);
  EXPECT_LT(ChamferPointToSurface(Sphere(), Sphere(), 20000, 3), 1e-12);
  // The paper's variant adds the sampling floor (in quadrature, per side).
  const double paper = ChamferPaper(Sphere(), big, 100000, 3);
  EXPECT_NEAR(paper, 2 * 0.1 * kR, 0.004);
  EXPECT_GT(paper, p2s - 0.001);
}

TEST(MetricsTest, HausdorffOfTranslatedBoxIsTheTranslation) {
  const Mesh a = Box(-1.0, 1.0);
  Mesh b = a;
  const Vec3 t(0.1, 0.05, 0.02);
  b.V.rowwise() += t.transpose();
  EXPECT_NEAR(HausdorffPaper(a, b), t.norm(), 1e-12);
  EXPECT_NEAR(HausdorffSampled(a, b, 20000, 1), t.norm(), 1e-12);
  EXPECT_EQ(HausdorffPaper(a, a), 0.0);
}

TEST(MetricsTest, SampledHausdorffSeesFaceInteriors) {
  // A: one big triangle. B: three tiny triangles at A's corners, in its
  // plane. Every vertex of either mesh is (nearly) on the other, but A's
  // interior around (1, 1) is about sqrt(2) from B.
  Mesh a;
  a.V.resize(3, 3);
  a.V << 0, 0, 0, 2, 0, 0, 0, 2, 0;
  a.F.resize(1, 3);
  a.F << 0, 1, 2;
  Mesh b;
  b.V.resize(9, 3);
  b.F.resize(3, 3);
  const double e = 0.05;
  for (int c = 0; c < 3; ++c) {
    const Vec3 p = a.V.row(c);
    b.V.row(3 * c) = p.transpose();
    b.V.row(3 * c + 1) = (p + Vec3(e, 0, 0)).transpose();
    b.V.row(3 * c + 2) = (p + Vec3(0, e, 0)).transpose();
    b.F.row(c) << 3 * c, 3 * c + 1, 3 * c + 2;
  }
  const double paper = HausdorffPaper(a, b);
  const double sampled = HausdorffSampled(a, b, 200000, 1);
  EXPECT_LT(paper, 0.1);
  EXPECT_GT(sampled, 1.3);
  EXPECT_LT(sampled, std::sqrt(2.0));
}

TEST(MetricsTest, EnergySdfOfExactSamplesIsZero) {
  const Mesh box = Box(-1.0, 1.0);
  Rng rng(5);
  SdfSamples s;
  const int n = 2000;
  s.points.resize(n, 3);
  s.values.resize(n);
  for (int i = 0; i < n; ++i) {
    Vec3 p;
    for (int a = 0; a < 3; ++a) p[a] = rng.Uniform(-2.0, 2.0);
    s.points.row(i) = p.transpose();
    const Vec3 q = p.cwiseAbs() - Vec3::Ones();
    // Exact signed distance to the box.
    s.values[i] = q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
  }
  EXPECT_LT(EnergySdf(s, box), 1e-20);
  // |s| off by 0.01 everywhere: 1000 * 0.01^2 = 0.1.
  SdfSamples off = s;
  for (int i = 0; i < n; ++i) off.values[i] += s.values[i] < 0 ? -0.01 : 0.01;
  EXPECT_NEAR(EnergySdf(off, box), 0.1, 1e-9);
  // Clamped samples (|s| >= clamp) are skipped.
  SdfSamples clamped = s;
  clamped.clamp = 0.3;
  int kept = 0;
  for (int i = 0; i < n; ++i) {
    if (std::abs(s.values[i]) >= 0.3) {
      clamped.values[i] = s.values[i] < 0 ? -0.3 : 0.3;
    } else {
      clamped.values[i] += s.values[i] < 0 ? -0.02 : 0.02;
      ++kept;
    }
  }
  ASSERT_GT(kept, 100);
  EXPECT_NEAR(EnergySdf(clamped, box), 1000 * 0.02 * 0.02, 1e-9);
}

TEST(MetricsTest, SameAtOneAndTwoThreads) {
  const Mesh big = Scaled(Sphere(), 1.05);
  double a, b, c, d;
  {
    ThreadLimit limit(1);
    a = ChamferPaper(Sphere(), big, 50000, 4);
    c = HausdorffSampled(Sphere(), big, 50000, 4);
  }
  {
    ThreadLimit limit(2);
    b = ChamferPaper(Sphere(), big, 50000, 4);
    d = HausdorffSampled(Sphere(), big, 50000, 4);
  }
  EXPECT_EQ(a, b);
  EXPECT_EQ(c, d);
}

TEST(MetricsTest, EmptyMeshesAndBadCountsThrow) {
  const Mesh empty;
  EXPECT_THROW(ChamferPaper(empty, Sphere(), 100), Error);
  EXPECT_THROW(ChamferPaper(Sphere(), empty, 100), Error);
  EXPECT_THROW(HausdorffPaper(Sphere(), empty), Error);
  EXPECT_THROW(ChamferPointToSurface(empty, Sphere(), 100), Error);
  EXPECT_THROW(HausdorffSampled(Sphere(), empty, 100), Error);
  SdfSamples s;
  s.points = MatrixXd::Zero(1, 3);
  s.values = VectorXd::Zero(1);
  EXPECT_THROW(EnergySdf(s, empty), Error);
  EXPECT_THROW(ChamferPaper(Sphere(), Sphere(), 0), Error);
  try {
    ChamferPaper(empty, Sphere(), 10);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("empty"), std::string::npos);
  }
}

}  // namespace
}  // namespace arcs
