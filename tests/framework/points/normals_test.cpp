// Normal estimation and orientation on analytic shapes: the estimated normal
// must match the true one up to sign within a few degrees (jet fit on exact
// samples), and the MST orientation must make every normal outward on a
// sphere and a torus (closed surfaces, one component).
#include "framework/error.h"
#include "framework/geometry/builtin_shapes.h"
#include "framework/points/normals.h"
#include "framework/points/sample_points.h"

#include <gtest/gtest.h>

#include <cmath>

namespace arcs {
namespace {

PointCloud Sample(const Mesh& m, int n) {
  SurfacePointOptions o;
  o.count = n;
  return SampleSurfacePoints(m, o, 3);
}

TEST(Normals, MstOrientsSphereOutward) {
  const PointCloud pc = Sample(MakeIcosphere(0.5, 4), 3000);
  NormalReport rep;
  const MatrixX3d N = EstimateNormals(pc.P, NormalOptions{}, &rep);
  EXPECT_EQ(rep.unoriented, 0);
  int inward = 0;
  double worst = 1.0;
  for (int i = 0; i < pc.Size(); ++i) {
    const double c = N.row(i).dot(pc.P.row(i).normalized());
    inward += c < 0;
    worst = std::min(worst, std::abs(c));
    EXPECT_NEAR(N.row(i).norm(), 1.0, 1e-9);
  }
  EXPECT_EQ(inward, 0);
  EXPECT_GT(worst, std::cos(5.0 * M_PI / 180));  // jet fit on exact samples of a 1280-face icosphere
}

TEST(Normals, MstOrientsTorusOutward) {
  const double R = 0.35;
  const PointCloud pc = Sample(MakeTorus(R, 0.15, 200, 100), 4000);
  const MatrixX3d N = EstimateNormals(pc.P, NormalOptions{});
  int inward = 0;
  for (int i = 0; i < pc.Size(); ++i) {
    const Vec3 p = pc.P.row(i);
    const Vec3 c = R * Vec3(p.x(), p.y(), 0).normalized();  // the tube's centre circle
    inward += N.row(i).dot(p - c) < 0;
  }
  EXPECT_EQ(inward, 0);
}

TEST(Normals, PcaAndCentroidOnSphere) {
  const PointCloud pc = Sample(MakeIcosphere(0.5, 4), 2000);
  NormalOptions o;
  o.method = "pca";
  o.orientation = "centroid";
  const MatrixX3d N = EstimateNormals(pc.P, o);
  for (int i = 0; i < pc.Size(); ++i) ASSERT_GT(N.row(i).dot(pc.P.row(i).normalized()), 0.95) << i;
}

TEST(Normals, Errors) {
  MatrixX3d P(2, 3);
  P << 0, 0, 0, 1, 0, 0;
  EXPECT_THROW(EstimateNormals(P, NormalOptions{}), Error);
  MatrixX3d Q = MatrixX3d::Random(10, 3);
  Q(4, 1) = NAN;
  try {
    EstimateNormals(Q, NormalOptions{});
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("point 4"), std::string::npos) << e.what();
  }
  NormalOptions bad;
  bad.orientation = "sideways";
  EXPECT_THROW(EstimateNormals(MatrixX3d::Random(10, 3), bad), OptionError);
}

}  // namespace
}  // namespace arcs
