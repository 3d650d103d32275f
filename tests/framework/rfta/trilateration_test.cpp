// Alg. 2's trilateration: the common points of three spheres, and the
// two-lane form of the pair loop held to the scalar form bit for bit.
#include "framework/rfta/trilateration.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

namespace arcs {
namespace {

using namespace trilateration;

TEST(Trilateration, UnitSpheresMeetAtTheKnownPoints) {
  // Unit spheres at the origin, e_x and e_y meet at (1/2, 1/2, +-1/sqrt(2)).
  Vec3 out[2];
  ASSERT_EQ(Trilaterate(Vec3::Zero(), 1.0, Vec3::UnitX(), 1.0, Vec3::UnitY(), 1.0, out), 2);
  for (const Vec3& p : out) {
    EXPECT_NEAR(p.x(), 0.5, 1e-15);
    EXPECT_NEAR(p.y(), 0.5, 1e-15);
    EXPECT_NEAR(std::abs(p.z()), std::sqrt(0.5), 1e-15);
    EXPECT_NEAR(p.norm(), 1.0, 1e-15);
    EXPECT_NEAR((p - Vec3::UnitX()).norm(), 1.0, 1e-15);
    EXPECT_NEAR((p - Vec3::UnitY()).norm(), 1.0, 1e-15);
  }
  EXPECT_NEAR(out[0].z(), -out[1].z(), 1e-15);
  // Collinear centres and spheres without a common point: none.
  EXPECT_EQ(Trilaterate(Vec3::Zero(), 1.0, Vec3::UnitX(), 1.0, 2.0 * Vec3::UnitX(), 1.0, out), 0);
  EXPECT_EQ(Trilaterate(Vec3::Zero(), 1.0, Vec3::UnitX(), 1.0, 5.0 * Vec3::UnitY(), 1.0, out), 0);
}

TEST(Trilateration, TwoLanesAreTheScalarFormBitForBit) {
  // Balls around a sphere as Alg. 2 pairs them (most pairs meet), with
  // concentric, collinear and tangent cases mixed in.
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0), ur(0.01, 1.0);
  long lanes = 0, with_points = 0;
  for (int it = 0; it < 200000; ++it) {
    const Vec3 c(u(rng), u(rng), u(rng));
    const double r = ur(rng);
    Vec3 pa[2];
    double ra[2];
    for (int k = 0; k < 2; ++k) {
      pa[k] = c + r * Vec3(u(rng), u(rng), u(rng));
      ra[k] = r * (0.5 + ur(rng));
    }
    Vec3 pb = c + r * Vec3(u(rng), u(rng), u(rng));
    const double rb = r * (0.5 + ur(rng));
    if (it % 5 == 0) pa[1] = c;                                   // concentric with the sphere
    if (it % 7 == 0) pb = pa[0];                                  // collinear centres
    if (it % 11 == 0) ra[0] = std::abs((pa[0] - c).norm() - r);   // tangent
    const TrilaterationBase base[2] = {TrilaterateBase(c, r, pa[0], ra[0]), TrilaterateBase(c, r, pa[1], ra[1])};
    const TrilaterationBase* const bp[2] = {&base[0], &base[1]};
    Vec3 two[2][2];
    int n2[2];
    TrilaterateWith2(bp, c, r, ra, pb, rb, two, n2);
    for (int k = 0; k < 2; ++k) {
      Vec3 one[2];
      const int n1 = TrilaterateWith(base[k], c, r, ra[k], pb, rb, one);
      ++lanes;
      ASSERT_EQ(n1, n2[k]) << "iteration " << it << ", lane " << k;
      with_points += n1 > 0;
      for (int t = 0; t < n1; ++t)
        ASSERT_EQ(std::memcmp(one[t].data(), two[k][t].data(), sizeof(double) * 3), 0)
            << "iteration " << it << ", lane " << k << ", point " << t;
    }
  }
  // The comparison saw both outcomes in numbers.
  EXPECT_GT(with_points, lanes / 4);
  EXPECT_LT(with_points, lanes);
}

}  // namespace
}  // namespace arcs
