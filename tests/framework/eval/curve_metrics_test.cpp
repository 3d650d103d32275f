// The curve metrics: Chamfer, Hausdorff and E_SDF on polylines.
#include "framework/eval/curve_metrics.h"
#include "framework/geometry/curves.h"
#include "framework/sdf/sdf2d.h"

#include <gtest/gtest.h>

#include <cmath>

namespace arcs {
namespace {

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
