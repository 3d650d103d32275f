#include "framework/geometry/normalize.h"

#include "framework/error.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

namespace arcs {
namespace {

Mesh Box() {
  Mesh m;
  m.V.resize(4, 3);
  m.V << 1, 2, 3,  //
      5, 2, 3,     //
      1, 4, 3,     //
      1, 2, 4;     // bbox [1,5] x [2,4] x [3,4]: longest side 4, centre (3,3,3.5)
  m.F.resize(1, 3);
  m.F << 0, 1, 2;
  return m;
}

TEST(NormalizeTest, CentresAndScalesLongestSide) {
  Mesh m = Box();
  const Similarity t = Normalize(&m, NormalizeOptions{});
  EXPECT_DOUBLE_EQ(t.scale, 0.25);
  const Vec3 lo = m.V.colwise().minCoeff(), hi = m.V.colwise().maxCoeff();
  EXPECT_NEAR((hi - lo).maxCoeff(), 1.0, 1e-15);
  EXPECT_NEAR((hi + lo).norm(), 0.0, 1e-15);
  EXPECT_NEAR(hi.x() - lo.x(), 1.0, 1e-15);
  EXPECT_NEAR(hi.y() - lo.y(), 0.5, 1e-15);
  // Round trip.
  const Mesh back = ApplyInverseSimilarity(t, m);
  EXPECT_TRUE(back.V.isApprox(Box().V, 1e-14));
}

TEST(NormalizeTest, RandomRotationIsSeededProperRotation) {
  NormalizeOptions o;
  o.random_rotation = true;
  o.rotation_seed = 1;
  Mesh a = Box(), b = Box(), c = Box();
  const Similarity ta = Normalize(&a, o);
  const Similarity tb = Normalize(&b, o);
  o.rotation_seed = 2;
  const Similarity tc = Normalize(&c, o);
  EXPECT_TRUE(ta.rotation == tb.rotation);
  EXPECT_FALSE(ta.rotation.isApprox(tc.rotation));
  EXPECT_TRUE((ta.rotation * ta.rotation.transpose()).isApprox(Eigen::Matrix3d::Identity(), 1e-14));
  EXPECT_NEAR(ta.rotation.determinant(), 1.0, 1e-14);
  EXPECT_FALSE(ta.rotation.isApprox(Eigen::Matrix3d::Identity(), 1e-3));
  // The rotation axis lies in the positive octant (axis = normalised U(0,1)^3).
  const Eigen::AngleAxisd aa(ta.rotation);
  const Vec3 axis = aa.angle() > 0 ? aa.axis() : Vec3(-aa.axis());
  EXPECT_TRUE((axis.array() >= -1e-12).all() || (axis.array() <= 1e-12).all());
  // Distances scale by `scale`; the inverse undoes it.
  const Vec3 p(1, 2, 3), q(-2, 0.5, 7);
  EXPECT_NEAR((ta.Apply(p) - ta.Apply(q)).norm(), ta.scale * (p - q).norm(), 1e-13);
  EXPECT_TRUE(ta.Inverse().Apply(ta.Apply(p)).isApprox(p, 1e-13));
  EXPECT_TRUE(ta.ApplyInverse(ta.Apply(q)).isApprox(q, 1e-13));
}

TEST(NormalizeTest, OptionsAndErrors) {
  NormalizeOptions o;
  o.longest_side = -1;
  EXPECT_THROW(o.Check(), OptionError);
  o.longest_side = 0.0;  // keep scale
  o.center = false;
  Mesh m = Box();
  const Similarity t = Normalize(&m, o);
  EXPECT_EQ(t.scale, 1.0);
  EXPECT_TRUE(m.V == Box().V);
  Mesh empty;
  EXPECT_THROW(Normalize(&empty, NormalizeOptions{}), Error);
  Mesh point;
  point.V = MatrixX3d::Ones(3, 3);
  EXPECT_THROW(Normalize(&point, NormalizeOptions{}), Error);
}

TEST(NormalizeTest, SdfSamplesScaleWithTheShape) {
  SdfSamples s;
  s.points = MatrixXd::Zero(2, 3);
  s.points.row(1) << 2, 2, 2;
  s.values = VectorXd::Constant(2, 0.5);
  s.clamp = 1.0;
  GridInfo g;
  g.dims = {2, 1, 1};
  g.min = {0, 0, 0};
  g.max = {2, 2, 2};
  s.grid = g;
  Similarity t;
  t.scale = 0.5;
  t.translation = Vec3(-1, -1, -1);
  ApplySimilarity(t, &s);
  EXPECT_TRUE(s.points.row(1).isApprox(Eigen::RowVector3d(0.5, 0.5, 0.5)));
  EXPECT_DOUBLE_EQ(s.values[0], 0.25);
  EXPECT_DOUBLE_EQ(s.clamp, 0.5);
  ASSERT_TRUE(s.grid.has_value());
  EXPECT_DOUBLE_EQ(s.grid->min[0], -0.5);
  EXPECT_DOUBLE_EQ(s.grid->max[2], 0.5);
}

}  // namespace
}  // namespace arcs
