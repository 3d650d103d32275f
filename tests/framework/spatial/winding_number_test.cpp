#include "framework/spatial/winding_number.h"

#include "framework/error.h"
#include "framework/util/parallel.h"
#include "framework/util/rng.h"
#include "tests/framework/spatial/spatial_test_meshes.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace arcs {
namespace {

using spatial_test::GridPoints;
using spatial_test::Icosphere;
using spatial_test::Torus;

TEST(WindingNumber, OctantTriangleIsOneEighth) {
  // The face of the unit octahedron in the positive octant subtends 1/8 of the
  // sphere from the origin; its normal (1,1,1) points away, so the sign is +.
  const Vec3 a(1, 0, 0), b(0, 1, 0), c(0, 0, 1);
  EXPECT_NEAR(TriangleSolidAngleOver4Pi(a, b, c, Vec3::Zero()), 0.125, 1e-15);
  EXPECT_NEAR(TriangleSolidAngleOver4Pi(a, c, b, Vec3::Zero()), -0.125, 1e-15);
  // Seen from the far side of its plane the sign flips, from within it it vanishes.
  EXPECT_LT(TriangleSolidAngleOver4Pi(a, b, c, Vec3(1, 1, 1)), 0.0);
  EXPECT_EQ(TriangleSolidAngleOver4Pi(a, b, c, Vec3(2, -1, 0)), 0.0);
}

TEST(WindingNumber, LargeSolidAngleAboveHalfSphere) {
  // A big triangle just below q covers nearly a hemisphere: |w| close to 1/2
  // (checks the atan2 branch with a negative denominator is not needed and
  // that the value stays continuous).
  const Vec3 a(-1000, -1000, 0), b(1000, -1000, 0), c(0, 2000, 0);
  const double w = TriangleSolidAngleOver4Pi(a, b, c, Vec3(0, 0, 1e-3));
  EXPECT_NEAR(w, -0.5, 1e-5);
}

TEST(WindingNumber, ExactSphereInsideOneOutsideZero) {
  const Mesh m = Icosphere(3, 1.0, Vec3(0.1, -0.2, 0.3));
  EXPECT_NEAR(WindingNumberExact(m, Vec3(0.1, -0.2, 0.3)), 1.0, 1e-12);
  EXPECT_NEAR(WindingNumberExact(m, Vec3(0.5, 0.1, 0.4)), 1.0, 1e-12);
  EXPECT_NEAR(WindingNumberExact(m, Vec3(2.0, 0.0, 0.0)), 0.0, 1e-12);
  EXPECT_NEAR(WindingNumberExact(m, Vec3(-5.0, 7.0, 1.0)), 0.0, 1e-12);
  MatrixX3d Q(3, 3);
  Q << 0.1, -0.2, 0.3, 3, 3, 3, 0.1, -0.2, 1.35;
  const VectorXd w = WindingNumbersExact(m, Q);
  EXPECT_NEAR(w[0], 1.0, 1e-12);
  EXPECT_NEAR(w[1], 0.0, 1e-12);
  EXPECT_NEAR(w[2], 0.0, 1e-12);
  // Reversed orientation gives -1 inside.
  Mesh r = m;
  r.F.col(1).swap(r.F.col(2));
  EXPECT_NEAR(WindingNumberExact(r, Vec3(0.1, -0.2, 0.3)), -1.0, 1e-12);
}

TEST(WindingNumber, BatchSumMatchesPerTriangleAtan2) {
  // The batch kernel uses its own vectorisable atan2; it must agree with the
  // libm-based per-triangle function to rounding, also close to the surface.
  const Mesh m = Torus(0.6, 0.25, 24, 12);
  Rng rng(11);
  MatrixX3d Q(300, 3);
  for (int i = 0; i < 200; ++i)
    for (int k = 0; k < 3; ++k) Q(i, k) = rng.Uniform(-1.0, 1.0);
  for (int i = 200; i < 300; ++i) {  // within 1e-9 .. 1e-3 of a face centroid
    const int f = static_cast<int>(rng.UniformInt(m.NumFaces()));
    const Vec3 a = m.V.row(m.F(f, 0)), b = m.V.row(m.F(f, 1)), c = m.V.row(m.F(f, 2));
    const Vec3 n = (b - a).cross(c - a).normalized();
    const double off = std::pow(10.0, rng.Uniform(-9.0, -3.0)) * (i % 2 ? 1 : -1);
    Q.row(i) = ((a + b + c) / 3.0 + off * n).transpose();
  }
  const VectorXd w = WindingNumbersExact(m, Q);
  for (int i = 0; i < Q.rows(); ++i) {
    double ref = 0.0;
    for (int f = 0; f < m.NumFaces(); ++f)
      ref += TriangleSolidAngleOver4Pi(m.V.row(m.F(f, 0)), m.V.row(m.F(f, 1)), m.V.row(m.F(f, 2)),
                                       Q.row(i));
    ASSERT_NEAR(w[i], ref, 1e-13) << i;
    EXPECT_EQ(WindingNumberExact(m, Q.row(i)), w[i]);
    if (i >= 200) {
      EXPECT_NEAR(w[i], i % 2 ? 0.0 : 1.0, 1e-6);
    }
  }
}

TEST(WindingNumber, OpenHemisphereIsFractional) {
  // Half of the sphere seen from the centre: 1/2.
  const Mesh s = Icosphere(4);
  std::vector<int> keep;
  for (int f = 0; f < s.NumFaces(); ++f) {
    const Vec3 c = (s.V.row(s.F(f, 0)) + s.V.row(s.F(f, 1)) + s.V.row(s.F(f, 2))) / 3.0;
    if (c.z() > 0) keep.push_back(f);
  }
  Mesh h;
  h.V = s.V;
  h.F.resize(keep.size(), 3);
  for (std::size_t i = 0; i < keep.size(); ++i) h.F.row(i) = s.F.row(keep[i]);
  EXPECT_NEAR(WindingNumberExact(h, Vec3::Zero()), 0.5, 0.02);
}

// Fast vs exact on a grid: identical inside/outside classification, small
// |dw|. For a closed mesh the exact winding number is 0 outside its bounding
// box (the point connects to infinity without crossing the surface), so the
// O(#F) brute force is only needed for nodes inside the box.
void CheckFastAgainstExact(const Mesh& m, int n, double lo, double hi, double max_dw) {
  const MatrixX3d Q = GridPoints(n, lo, hi);
  const Vec3 blo = m.V.colwise().minCoeff().transpose(), bhi = m.V.colwise().maxCoeff().transpose();
  std::vector<int> inside_box;
  for (int i = 0; i < Q.rows(); ++i) {
    const Vec3 q = Q.row(i);
    if ((q.array() >= blo.array()).all() && (q.array() <= bhi.array()).all()) inside_box.push_back(i);
  }
  MatrixX3d Qb(inside_box.size(), 3);
  for (std::size_t k = 0; k < inside_box.size(); ++k) Qb.row(k) = Q.row(inside_box[k]);
  const VectorXd exact_box = WindingNumbersExact(m, Qb);
  VectorXd exact = VectorXd::Zero(Q.rows());
  for (std::size_t k = 0; k < inside_box.size(); ++k) exact[inside_box[k]] = exact_box[k];
  const FastWindingNumber fwn(m);
  const VectorXd fast = fwn.Eval(Q);
  int sign_errors = 0, inside = 0;
  double worst = 0.0;
  for (int i = 0; i < Q.rows(); ++i) {
    if ((exact[i] > 0.5) != (fast[i] > 0.5)) ++sign_errors;
    inside += exact[i] > 0.5;
    worst = std::max(worst, std::abs(exact[i] - fast[i]));
  }
  EXPECT_EQ(sign_errors, 0);
  EXPECT_GT(inside, 0);
  EXPECT_LE(worst, max_dw);
  EXPECT_DOUBLE_EQ(fwn.Eval(Vec3(Q.row(7))), fast[7]);
}

TEST(FastWindingNumber, TorusSignsMatchExactOnGrid) {
  const Mesh m = Torus(0.6, 0.25, 64, 32);
  CheckFastAgainstExact(m, 32, -1.0, 1.0, 0.01);
  // Values on the torus: inside the tube 1, in the hole 0, far away 0.
  const FastWindingNumber fwn(m);
  EXPECT_NEAR(fwn.Eval(Vec3(0.6, 0, 0)), 1.0, 0.01);
  EXPECT_NEAR(fwn.Eval(Vec3(0, 0, 0)), 0.0, 0.01);
  EXPECT_NEAR(fwn.Eval(Vec3(5, 1, 0)), 0.0, 1e-6);
  const FastWindingNumber precise(m, {.beta = 16.0});
  EXPECT_NEAR(precise.Eval(Vec3(0.6, 0, 0)), 1.0, 1e-6);
}

TEST(FastWindingNumber, LargerBetaAndOrderAreMoreAccurate) {
  // The centre of a sphere is the worst case (every cluster is seen from its
  // centre of curvature); measured errors there: order 2 beta 2: 5e-3, beta 4:
  // 1.7e-4, beta 8: 7e-6; order 0 beta 4: 6e-3.
  const Mesh m = Icosphere(4, 0.5);
  const MatrixX3d Q = GridPoints(12, -1.0, 1.0);
  const VectorXd exact = WindingNumbersExact(m, Q);
  auto err = [&](double beta, int order) {
    return (FastWindingNumber(m, {.beta = beta, .expansion_order = order}).Eval(Q) - exact).cwiseAbs().maxCoeff();
  };
  const double e2 = err(2.0, 2), e4 = err(4.0, 2), e8 = err(8.0, 2);
  EXPECT_LT(e2, 1e-2);
  EXPECT_LT(e4, e2 / 10);
  EXPECT_LT(e8, e4 / 10);
  EXPECT_LT(e8, 2e-5);
  EXPECT_LT(e4, err(4.0, 0) / 10);
  EXPECT_LT(err(4.0, 1), 0.05);
}

TEST(FastWindingNumber, DeterministicAcrossThreads) {
  const Mesh m = Torus(0.6, 0.25, 40, 20);
  const FastWindingNumber fwn(m);
  const MatrixX3d Q = GridPoints(20, -1, 1);
  VectorXd a, b;
  {
    ThreadLimit one(1);
    a = fwn.Eval(Q);
  }
  {
    ThreadLimit two(2);
    b = fwn.Eval(Q);
  }
  EXPECT_EQ(a, b);
}

TEST(FastWindingNumber, OptionsAreChecked) {
  const Mesh m = Icosphere(1);
  EXPECT_THROW(FastWindingNumber(m, {.beta = 0.5}), OptionError);
  EXPECT_THROW(FastWindingNumber(m, {.beta = NAN}), OptionError);
  EXPECT_THROW(FastWindingNumber(m, {.expansion_order = 3}), OptionError);
  EXPECT_THROW(FastWindingNumber(m, {.expansion_order = -1}), OptionError);
  EXPECT_NO_THROW(FastWindingNumber(m, {.beta = 1.0}));
}

TEST(FastWindingNumber, TinyMeshesSignsMatchExact) {
  ARCS_REQUIRE_SHARED_DATA();
  const auto rows = spatial_test::ReadManifest(testing::SharedData("tiny/MANIFEST.tsv"));
  ASSERT_FALSE(rows.empty());
  for (const auto& row : rows) {
    if (row.at("closed") != "True") continue;
    SCOPED_TRACE(row.at("file"));
    Mesh m = spatial_test::ReadObjVF(testing::SharedData("tiny/" + row.at("file")));
    spatial_test::NormalizeUnitBox(&m);
    // The RFTA grid covers [-1, 1]^3; the mesh spans [-0.5, 0.5].
    CheckFastAgainstExact(m, 32, -1.0, 1.0, 0.02);
  }
}

}  // namespace
}  // namespace arcs
