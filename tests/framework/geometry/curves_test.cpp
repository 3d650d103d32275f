// Built-in curves and polyline files.
#include "framework/geometry/curves.h"
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

}  // namespace
}  // namespace arcs
