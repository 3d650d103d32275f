// Degenerate and corrupted input to the point-cloud reconstructors: too few
// points, missing normals, non-finite values, coplanar points, duplicates,
// outliers. Each gives a clear error or the documented result
// (docs/point_reconstructors.md).
#include "framework/geometry/builtin_shapes.h"
#include "framework/points/point_reconstructors.h"
#include "framework/points/point_utils.h"
#include "framework/points/sample_points.h"
#include "framework/spatial/topology.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>

namespace arcs {
namespace {

template <class F>
std::string ErrorOf(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}
bool Has(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

PointCloud SpherePoints(int n, double outliers = 0, double duplicates = 0) {
  SurfacePointOptions o;
  o.count = n;
  o.outlier_fraction = outliers;
  o.duplicate_fraction = duplicates;
  return SampleSurfacePoints(MakeIcosphere(0.5, 4), o, 11);
}

TEST(ReconDegenerate, FewerThanFourPoints) {
  PointCloud pc;
  pc.P = MatrixX3d::Random(3, 3);
  pc.N = MatrixX3d::Random(3, 3);
  const Context ctx;
  for (const std::string& e : {ErrorOf([&] { ReconstructAlphaShape(pc, {}, ctx); }),
                               ErrorOf([&] { ReconstructAdvancingFront(pc, {}, ctx); }),
                               ErrorOf([&] { ReconstructBallPivoting(pc, {}, ctx); })})
    EXPECT_TRUE(Has(e, "needs at least 4 points, got 3")) << e;
  // Four rows, but only three distinct positions.
  pc.P = MatrixX3d::Random(4, 3);
  pc.P.row(3) = pc.P.row(0);
  pc.N = MatrixX3d::Ones(4, 3);
  const std::string e = ErrorOf([&] { ReconstructAlphaShape(pc, {}, ctx); });
  EXPECT_TRUE(Has(e, "4 distinct points, got 3 (1 duplicates)")) << e;
}

TEST(ReconDegenerate, MissingOrBadNormals) {
  PointCloud pc = SpherePoints(500);
  pc.N.resize(0, 3);
  const std::string e = ErrorOf([&] { ReconstructBallPivoting(pc, {}, Context()); });
  EXPECT_TRUE(Has(e, "ball_pivoting: needs oriented points")) << e;
  EXPECT_TRUE(Has(e, "estimate_normals")) << e;
  // Alpha shapes and advancing front do not need normals.
  EXPECT_GT(ReconstructAlphaShape(pc, {}, Context()).NumFaces(), 0);
  pc = SpherePoints(500);
  pc.N.row(17).setZero();
  EXPECT_TRUE(Has(ErrorOf([&] { ReconstructBallPivoting(pc, {}, Context()); }), "point 17 has a zero normal"));
  pc.N.row(17) << NAN, 0, 0;
  EXPECT_TRUE(Has(ErrorOf([&] { ReconstructBallPivoting(pc, {}, Context()); }), "point 17 has a non-finite normal"));
}

TEST(ReconDegenerate, NonFiniteCoordinate) {
  PointCloud pc = SpherePoints(500);
  pc.P(42, 2) = INFINITY;
  EXPECT_TRUE(Has(ErrorOf([&] { ReconstructAlphaShape(pc, {}, Context()); }),
                  "alpha_shape: point 42 has a non-finite coordinate"));
}

TEST(ReconDegenerate, CoplanarPoints) {
  // A 10 x 10 planar grid with +z normals.
  PointCloud pc;
  pc.P.resize(100, 3);
  pc.N.resize(100, 3);
  for (int i = 0; i < 100; ++i) {
    pc.P.row(i) << i % 10, i / 10, 0;
    pc.N.row(i) << 0, 0, 1;
  }
  // Alpha shapes bound a volume: none here.
  EXPECT_TRUE(Has(ErrorOf([&] { ReconstructAlphaShape(pc, {}, Context()); }), "coplanar"));
  // Ball pivoting triangulates the open patch, faces along the normals.
  const Mesh m = ReconstructBallPivoting(pc, {}, Context());
  const Topology t = ComputeTopology(m);
  EXPECT_NEAR(t.area, 81.0, 1e-9);
  for (int f = 0; f < m.NumFaces(); ++f) {
    const Vec3 a = m.V.row(m.F(f, 0)), b = m.V.row(m.F(f, 1)), c = m.V.row(m.F(f, 2));
    EXPECT_GT((b - a).cross(c - a).z(), 0);
  }
}

TEST(ReconDegenerate, DuplicatesAreMerged) {
  const PointCloud clean = SpherePoints(3000);
  const PointCloud dup = SpherePoints(3000, 0.0, 0.2);  // same first 3000 rows + 600 copies
  ASSERT_EQ(dup.Size(), 3600);
  PointReconstructionReport r1, r2;
  const Mesh a = ReconstructAlphaShape(clean, {}, Context(), &r1);
  const Mesh b = ReconstructAlphaShape(dup, {}, Context(), &r2);
  EXPECT_EQ(r1.duplicates_removed, 0);
  EXPECT_GT(r2.duplicates_removed, 500);  // draws with replacement: some rows copied twice
  EXPECT_EQ(r2.points_used, 3000);
  EXPECT_EQ(a.NumFaces(), b.NumFaces());
  // The cleaned cloud is the clean one, row for row: the same mesh.
  EXPECT_EQ(ReconstructBallPivoting(dup, {}, Context()).F, ReconstructBallPivoting(clean, {}, Context()).F);
}

TEST(ReconDegenerate, Outliers) {
  // 1 % outliers, uniform in the padded bounding box (most far from the
  // sphere). No reconstructor removes outliers (documented); what happens:
  const PointCloud pc = SpherePoints(4000, 0.01);
  // Ball pivoting only connects points a few spacings apart: isolated
  // outliers are left out, the sphere stays one piece of the right area.
  {
    const Topology t = ComputeTopology(ReconstructBallPivoting(pc, {}, Context()));
    EXPECT_LT(t.referenced_vertices, 4040);
    EXPECT_GE(t.referenced_vertices, 3990);
    EXPECT_NEAR(t.area, M_PI, 0.05 * M_PI);
  }
  // The automatic alpha (rule optimal) is the smallest alpha whose solid
  // contains every point, outliers included: the solid swells to reach them.
  // Still closed by construction, but far from the sphere.
  {
    const Topology t = ComputeTopology(ReconstructAlphaShape(pc, {}, Context()));
    EXPECT_TRUE(t.closed);
    EXPECT_GT(t.area, 1.2 * M_PI);
    // An explicit radius (about the sphere's) is how to use alpha shapes on such
    // clouds; on the clean sphere it gives the sphere.
    AlphaShapeOptions o;
    o.radius = 0.6;
    const Topology u = ComputeTopology(ReconstructAlphaShape(SpherePoints(4000), o, Context()));
    EXPECT_EQ(u.genus, 0);
    EXPECT_NEAR(u.area, M_PI, 0.01 * M_PI);
  }
}

TEST(ReconDegenerate, PointSpacing) {
  MatrixX3d P(4, 3);
  P << 0, 0, 0, 1, 0, 0, 1, 0, 0, 3, 0, 0;  // coincident rows are skipped
  EXPECT_NEAR(PointSpacing(P), (1.0 + 1.0 + 1.0 + 2.0) / 4.0, 1e-12);
  MatrixX3d Q = MatrixX3d::Zero(5, 3);
  EXPECT_THROW(PointSpacing(Q), Error);
}

TEST(ReconDegenerate, OptionsChecked) {
  BallPivotingOptions b;
  b.levels = 0;
  EXPECT_THROW(ReconstructBallPivoting(SpherePoints(100), b, Context()), OptionError);
  AlphaShapeOptions a;
  a.rule = "best";
  EXPECT_THROW(ReconstructAlphaShape(SpherePoints(100), a, Context()), OptionError);
}

}  // namespace
}  // namespace arcs
