// Pseudo-SDF of a swept volume: a sphere swept along a segment is a capsule,
// whose exact SDF is known. Outside, min-over-poses is the distance to the
// union of the poses (close to the capsule's for many poses); inside it only
// bounds the depth from below.
#include "framework/geometry/builtin_shapes.h"
#include "framework/sdf/pseudo_sdf.h"

#include <gtest/gtest.h>

#include <cmath>

namespace arcs {
namespace {

double CapsuleSdf(const Vec3& x, const Vec3& a, const Vec3& b, double r) {
  const Vec3 ab = b - a;
  const double t = std::clamp((x - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (x - (a + t * ab)).norm() - r;
}

TEST(PseudoSdf, SweptSphereIsACapsuleOutsideAndABoundInside) {
  const double r = 0.25;
  const Mesh sphere = MakeIcosphere(r, 3, Vec3::Zero());
  SweepOptions o;
  o.translation = Vec3(0.4, 0, 0);
  o.steps = 41;
  SdfGridOptions g;
  g.n = 16;
  const SdfSamples s = SampleSweptSdfGrid(sphere, o, g, Context(1));
  EXPECT_EQ(s.bound_sign, -1);
  ASSERT_TRUE(s.grid.has_value());
  int inside = 0, outside = 0;
  for (std::int64_t i = 0; i < s.Size(); ++i) {
    const Vec3 x = s.points.row(i).transpose();
    const double exact = CapsuleSdf(x, Vec3::Zero(), o.translation, r);
    // Polyhedral sphere (~8e-3 below r) and 41 discrete poses (sagitta ~2e-4).
    if (exact > 0) {
      EXPECT_NEAR(s.values[i], exact, 8e-3) << i;
      ++outside;
    } else {
      // Depth is never over-estimated: |s| <= true depth (+ tolerance).
      EXPECT_LE(s.values[i], 8e-3) << i;
      EXPECT_GE(s.values[i], exact - 8e-3) << i;
      ++inside;
    }
  }
  EXPECT_GT(inside, 20);
  EXPECT_GT(outside, 1000);
}

TEST(PseudoSdf, RotationSweepsAndPosesAreConsistent) {
  // Two spheres of different sizes: a rotation about the bounding-box centre moves them.
  Mesh box = MakeIcosphere(0.2, 2, Vec3(0.3, 0, 0));
  const Mesh small = MakeIcosphere(0.1, 2, Vec3(-0.2, 0, 0));
  const int nv = box.NumVertices(), nf = box.NumFaces();
  box.V.conservativeResize(nv + small.NumVertices(), 3);
  box.V.bottomRows(small.NumVertices()) = small.V;
  box.F.conservativeResize(nf + small.NumFaces(), 3);
  box.F.bottomRows(small.NumFaces()) = small.F.array() + nv;
  SweepOptions o;
  o.translation = Vec3(0, 0.1, 0);
  o.angle_deg = 90;
  o.steps = 5;
  const Mesh poses = SweepPoses(box, o);
  EXPECT_EQ(poses.NumFaces(), 5 * box.NumFaces());
  // Every vertex of every pose lies on the swept solid's surface or inside.
  const VectorXd v = SweptSignedDistance(box, o, poses.V);
  EXPECT_LE(v.maxCoeff(), 1e-9);
  EXPECT_LT(v.minCoeff(), -0.01);  // the poses overlap: some vertices are inside others
}

TEST(PseudoSdf, BadOptionsAreRefused) {
  const Mesh sphere = MakeIcosphere(0.2, 1, Vec3::Zero());
  SweepOptions o;
  o.steps = 1;
  EXPECT_THROW(SweepPoses(sphere, o), OptionError);
  EXPECT_THROW(SweepPoses(Mesh{}, SweepOptions{}), Error);
}

}  // namespace
}  // namespace arcs
