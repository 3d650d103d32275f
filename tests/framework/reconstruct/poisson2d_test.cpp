// The 2D screened Poisson reconstructor on exact oriented samples of known
// curves, and marching squares on an exact 2D SDF grid.
#include "framework/eval/curve_metrics.h"
#include "framework/geometry/curves.h"
#include "framework/geometry/marching_cubes.h"
#include "framework/reconstruct/poisson2d.h"
#include "framework/sdf/sdf2d.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace arcs {
namespace {

// `count` points evenly spaced on each closed component of `c` with the
// outward normals (right of every edge, as the inside lies on the left).
PointCloud OrientedSamples(const Polyline& c, int stride) {
  PointCloud pc;
  const int k = (c.NumEdges() + stride - 1) / stride;
  pc.P.resize(k, 3);
  pc.N.resize(k, 3);
  for (int j = 0; j < k; ++j) {
    const int e = j * stride;
    const Vec3 a = c.V.row(c.E(e, 0)).transpose(), b = c.V.row(c.E(e, 1)).transpose();
    const Vec3 d = (b - a).normalized();
    pc.P.row(j) = (0.5 * (a + b)).transpose();
    pc.N.row(j) << d.y(), -d.x(), 0.0;
  }
  return pc;
}

TEST(Poisson2D, ReconstructsACircleAndAnEllipseFromExactSamples) {
  for (const char* name : {"circle", "ellipse"}) {
    const Polyline ref = MakeBuiltinCurve(name, 2048);
    const PointCloud pc = OrientedSamples(ref, 8);  // 256 points
    Poisson2DInfo info;
    const Polyline out = ReconstructPoisson2D(pc, Poisson2DOptions{}, Context(1), &info);
    const CurveTopology t = ComputeCurveTopology(out);
    EXPECT_EQ(t.components, 1) << name;
    EXPECT_TRUE(t.Closed()) << name;
    EXPECT_GT(PolylineSignedArea(out), 0) << name << ": the output must run counter-clockwise";
    EXPECT_EQ(info.resolution, 64);
    // Measured: circle 0.00025, ellipse 0.00044 (cell size 0.0195).
    EXPECT_LT(HausdorffCurves(out, ref, 20000), 0.002) << name;
    EXPECT_NEAR(PolylineSignedArea(out), PolylineSignedArea(ref), 0.01 * PolylineSignedArea(ref)) << name;
  }
}

TEST(Poisson2D, FinerGridIsMoreAccurateAndHolesRunClockwise) {
  const Polyline ref = MakeBuiltinCurve("annulus", 3072);
  const PointCloud pc = OrientedSamples(ref, 6);  // 512 points
  Poisson2DOptions coarse, fine;
  coarse.resolution = 64;
  fine.resolution = 256;
  const Polyline a = ReconstructPoisson2D(pc, coarse, Context(1));
  const Polyline b = ReconstructPoisson2D(pc, fine, Context(1));
  for (const Polyline* out : {&a, &b}) {
    const CurveTopology t = ComputeCurveTopology(*out);
    EXPECT_EQ(t.components, 2);
    EXPECT_EQ(t.holes, 1) << "the inner circle must run clockwise";
    EXPECT_TRUE(t.Closed());
  }
  const double ha = HausdorffCurves(a, ref, 20000), hb = HausdorffCurves(b, ref, 20000);
  EXPECT_LT(hb, ha);  // measured 0.00043 at 64 cells, 0.00003 at 256
  EXPECT_LT(hb, 0.0002);
}

TEST(Poisson2D, BadInputIsAClearError) {
  const PointCloud good = OrientedSamples(MakeBuiltinCurve("circle", 256), 8);
  PointCloud few = good;
  few.P.conservativeResize(2, 3);
  few.N.conservativeResize(2, 3);
  EXPECT_THROW(ReconstructPoisson2D(few, Poisson2DOptions{}, Context(1)), Error);
  PointCloud nan = good;
  nan.P(3, 0) = std::nan("");
  EXPECT_THROW(ReconstructPoisson2D(nan, Poisson2DOptions{}, Context(1)), Error);
  PointCloud nonormals = good;
  nonormals.N.resize(0, 3);
  EXPECT_THROW(ReconstructPoisson2D(nonormals, Poisson2DOptions{}, Context(1)), Error);
  PointCloud lifted = good;
  lifted.P(0, 2) = 0.1;
  EXPECT_THROW(ReconstructPoisson2D(lifted, Poisson2DOptions{}, Context(1)), Error);
  PointCloud same = good;
  same.P.rowwise() = good.P.row(0);
  EXPECT_THROW(ReconstructPoisson2D(same, Poisson2DOptions{}, Context(1)), Error);
  Poisson2DOptions bad;
  bad.screening = -1;
  EXPECT_THROW(ReconstructPoisson2D(good, bad, Context(1)), OptionError);
}

TEST(MarchingSquares2D, CircleGridGivesOneClosedCounterClockwiseCurve) {
  const Polyline ref = MakeBuiltinCurve("circle", 2048);
  SdfGrid2DOptions o;
  o.n = 20;
  const SdfSamples s = SampleSdfGrid2D(ref, o, Context(1));
  const Polyline ms = ToPolyline(MarchingSquares(s.values, *s.grid));
  const CurveTopology t = ComputeCurveTopology(ms);
  EXPECT_EQ(t.components, 1);
  EXPECT_TRUE(t.Closed());
  EXPECT_GT(PolylineSignedArea(ms), 0);
  // Vertices interpolate an exact SDF: within the linear-interpolation error of the grid (h = 0.1).
  for (int v = 0; v < ms.NumVertices(); ++v) EXPECT_NEAR(ms.V.row(v).norm(), 0.5, 0.01);
  EXPECT_LT(ChamferCurves(ms, ref, 20000), 0.01);
}

}  // namespace
}  // namespace arcs
