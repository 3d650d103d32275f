// Built-in curves, polyline files, the exact 2D SDF and the curve metrics.
#include "framework/planar/curve_metrics.h"
#include "framework/planar/curves.h"
#include "framework/planar/polyline_query.h"
#include "framework/planar/sdf2d.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>

namespace arcs {
namespace {

using testing::ExpectInputError;

TEST(BuiltinCurves, ClosedCounterClockwiseWithTheRightComponents) {
  for (const std::string& name : BuiltinCurveNames()) {
    const Polyline c = MakeBuiltinCurve(name, 512);
    ASSERT_NO_THROW(CheckPolyline(c, name));
    const CurveTopology t = ComputeCurveTopology(c);
    EXPECT_TRUE(t.Closed()) << name;
    EXPECT_EQ(t.open_ends, 0) << name;
    EXPECT_EQ(t.branch_vertices, 0) << name;
    EXPECT_GT(PolylineSignedArea(c), 0) << name << ": outer boundaries must run counter-clockwise";
    EXPECT_EQ(t.components, name == "two_circles" || name == "annulus" ? 2 : 1) << name;
    EXPECT_EQ(t.holes, name == "annulus" ? 1 : 0) << name;
    const double extent = (c.V.colwise().maxCoeff() - c.V.colwise().minCoeff()).maxCoeff();
    EXPECT_GT(extent, 0.6) << name;
    EXPECT_LE(extent, 1.0 + 1e-9) << name;
  }
  constexpr double kPi = std::numbers::pi;
  EXPECT_NEAR(PolylineSignedArea(MakeBuiltinCurve("circle", 2048)), kPi * 0.25, 1e-4);
  EXPECT_NEAR(PolylineSignedArea(MakeBuiltinCurve("annulus", 2048)), kPi * (0.25 - 0.0625), 1e-4);
  EXPECT_NEAR(PolylineLength(MakeBuiltinCurve("circle", 2048)), kPi, 1e-5);
  EXPECT_THROW(MakeBuiltinCurve("dodecahedron"), Error);
  EXPECT_THROW(MakeBuiltinCurve("circle", 3), OptionError);
}

TEST(BuiltinCurves, NormalizeToLongestSideOneCentred) {
  Polyline c = MakeBuiltinCurve("bunny", 256);
  c.V *= 3.0;
  c.V.col(0).array() += 5.0;
  NormalizeCurve(&c);
  const Eigen::RowVector3d lo = c.V.colwise().minCoeff(), hi = c.V.colwise().maxCoeff();
  EXPECT_NEAR((hi - lo).maxCoeff(), 1.0, 1e-12);
  EXPECT_NEAR((lo + hi).x(), 0.0, 1e-12);
  EXPECT_NEAR((lo + hi).y(), 0.0, 1e-12);
  EXPECT_EQ(c.V.col(2).cwiseAbs().maxCoeff(), 0.0);
}

TEST(PolylineFiles, RoundTripAndSvg) {
  const std::string dir = testing::TempDir("planar_files").string();
  const Polyline c = MakeBuiltinCurve("annulus", 64);
  const std::string path = dir + "/annulus.obj";
  WritePolyline(path, c);
  const Polyline back = ReadPolyline(path);
  ASSERT_EQ(back.NumVertices(), c.NumVertices());
  ASSERT_EQ(back.NumEdges(), c.NumEdges());
  EXPECT_EQ((back.V - c.V).cwiseAbs().maxCoeff(), 0.0) << "shortest round-trip decimals";
  EXPECT_NEAR(PolylineSignedArea(back), PolylineSignedArea(c), 1e-15);
  EXPECT_EQ(ComputeCurveTopology(back).holes, 1);
  WritePolyline(dir + "/annulus.svg", c);
  std::ifstream svg(dir + "/annulus.svg");
  std::string first;
  std::getline(svg, first);
  EXPECT_NE(first.find("<svg"), std::string::npos);
  EXPECT_THROW(WritePolyline(dir + "/x.stl", c), Error);
}

TEST(PolylineFiles, MalformedFilesNameTheLine) {
  const std::string dir = testing::TempDir("planar_bad").string();
  auto write = [&](const std::string& text) {
    const std::string p = dir + "/bad.obj";
    std::ofstream(p) << text;
    return p;
  };
  ExpectInputError([&] { ReadPolyline(write("v 0 0\nv 1 0\nv 0 x\nl 1 2 3 1\n")); }, {"bad.obj:3"});
  ExpectInputError([&] { ReadPolyline(write("v 0 0\nv 1 0\nl 1 2 5\n")); }, {"bad.obj:3"});
  ExpectInputError([&] { ReadPolyline(write("v 0 0 1\n")); }, {"bad.obj:1"});
  ExpectInputError([&] { ReadPolyline(write("v 0 0\nv 1 0\nv 0 1\nf 1 2 3\n")); }, {"bad.obj:4"});
  ExpectInputError([&] { ReadPolyline(write("v 0 0\nv 1 nan\nl 1 2\n")); }, {"bad.obj:2"});
  ExpectInputError([&] { ReadPolyline(write("# only vertices\nv 0 0\n")); }, {"no edges"});
  ExpectInputError([&] { ReadPolyline(dir + "/missing.obj"); }, {"missing.obj"});
  // OBJ relative indices and comments are accepted.
  const Polyline tri = ReadPolyline(write("v 0 0 # a\nv 1 0\nv 0 1\nl -3 -2 -1 -3\n"));
  EXPECT_EQ(tri.NumEdges(), 3);
  EXPECT_TRUE(ComputeCurveTopology(tri).Closed());
  EXPECT_NEAR(PolylineSignedArea(tri), 0.5, 1e-15);
}

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

TEST(PolylineQuery, ClosestPointMatchesBruteForceAndWindingNumbers) {
  const Polyline c = MakeBuiltinCurve("star", 300);
  const SegmentBvh bvh(c);
  Rng rng(3);
  for (int k = 0; k < 300; ++k) {
    const Vec3 q(rng.Uniform(-0.8, 0.8), rng.Uniform(-0.8, 0.8), 0);
    double best = 1e300;
    for (int e = 0; e < c.NumEdges(); ++e) {
      const Eigen::Vector2d a = c.V.row(c.E(e, 0)).head<2>(), b = c.V.row(c.E(e, 1)).head<2>();
      const double t = std::clamp((q.head<2>() - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
      best = std::min(best, (a + t * (b - a) - q.head<2>()).squaredNorm());
    }
    const SegmentBvh::Hit h = bvh.Closest(q);
    EXPECT_NEAR(h.sq_dist, best, 1e-15);
    EXPECT_NEAR((h.point - q).squaredNorm(), h.sq_dist, 1e-15);
  }
  const Polyline ann = MakeBuiltinCurve("annulus", 256);
  EXPECT_NEAR(WindingNumber2D(ann, Vec3(0, 0, 0)), 0.0, 1e-12);
  EXPECT_NEAR(WindingNumber2D(ann, Vec3(0.37, 0.05, 0)), 1.0, 1e-12);
  EXPECT_NEAR(WindingNumber2D(ann, Vec3(0.9, 0, 0)), 0.0, 1e-12);
}

TEST(CurveMetrics, KnownDistancesAndSamplingFloor) {
  const Polyline a = MakeBuiltinCurve("circle", 2048);
  Polyline b = a;
  b.V *= 1.1;  // concentric circle of radius 0.55: every distance is 0.05 (up to the chords)
  EXPECT_NEAR(HausdorffCurves(a, b), 0.05, 1e-5);
  EXPECT_NEAR(HausdorffCurves(a, b, 0), 0.05, 1e-5);
  EXPECT_NEAR(ChamferCurves(a, b, 20000, 1), 0.1, 1e-3);
  const double floor = ChamferCurves(a, a, 100000, 1);
  EXPECT_GT(floor, 0.0);
  EXPECT_LT(floor, 1e-4);
  // Seeded: the same seed gives the same value.
  EXPECT_EQ(ChamferCurves(a, b, 1000, 7), ChamferCurves(a, b, 1000, 7));
  Polyline empty;
  EXPECT_THROW(ChamferCurves(empty, a), Error);
  EXPECT_THROW(HausdorffCurves(a, empty), Error);
  // E_SDF of the exact samples against the curve itself is ~0.
  const SdfSamples s = SampleSdfGrid2D(a, SdfGrid2DOptions{}, Context(1));
  EXPECT_LT(EnergySdf2D(s, a), 1e-9);
  double expect = 0;
  for (int i = 0; i < s.Size(); ++i) {
    const double r = s.points.row(i).norm(), d = std::abs(r - 0.5) - std::abs(r - 0.55);
    expect += d * d;
  }
  EXPECT_NEAR(EnergySdf2D(s, b), 1000 * expect / s.Size(), 1e-4);
}

}  // namespace
}  // namespace arcs
