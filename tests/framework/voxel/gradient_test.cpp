// Analytic gradients of the per-triangle winding terms (Alg. 1 atan2 solid
// angle and the eq. 4 naive term) and of the occupancy loss, checked against
// central finite differences.
//
// Tolerances: central differences with step h have truncation error
// ≈ h² |f'''| / 6 and round-off ≈ ε |f| / h. The nearest query below is at
// distance d = 1e-2 from a unit-size triangle, where |f'''| ≲ C / d³ (solid
// angle) or C / d⁵ (naive term, which itself grows like 1/d²) while
// |f'| ≳ 1 / d (resp. 1 / d³): with h = 1e-7 the relative truncation error is
// ≲ h² / d² = 1e-10 and the round-off ≲ 1e-16 / 1e-7 / |f'| ≤ 1e-9 relative.
// We assert 1e-6 relative (norm over all components): three orders of margin,
// yet a wrong sign, a missing factor or a swapped vertex gives O(1).
#include "framework/error.h"
#include "framework/geometry/builtin_shapes.h"
#include "framework/spatial/winding_number.h"
#include "framework/util/parallel.h"
#include "framework/util/rng.h"
#include "framework/voxel/gradient.h"
#include "framework/voxel/soft_occupancy.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>

namespace arcs {
namespace {

constexpr double kRelTol = 1e-6;

struct Tri {
  Vec3 v[3];
};

// Central differences of a per-triangle term with respect to its 9 corner coordinates.
void FdTermGrad(WindingForm form, const Tri& t, const Vec3& q, double h, Vec3 out[3]) {
  for (int j = 0; j < 3; ++j)
    for (int k = 0; k < 3; ++k) {
      Tri p = t, m = t;
      p.v[j][k] += h;
      m.v[j][k] -= h;
      const double fp = WindingTermGrad(form, p.v[0], p.v[1], p.v[2], q, nullptr);
      const double fm = WindingTermGrad(form, m.v[0], m.v[1], m.v[2], q, nullptr);
      out[j][k] = (fp - fm) / (2 * h);
    }
}

double RelErr(const Vec3 a[3], const Vec3 b[3]) {
  double num = 0, den = 0;
  for (int j = 0; j < 3; ++j) {
    num += (a[j] - b[j]).squaredNorm();
    den += b[j].squaredNorm();
  }
  return std::sqrt(num / den);
}

const Tri kTri{{Vec3(0.1, -0.2, 0.05), Vec3(1.0, 0.1, -0.1), Vec3(0.2, 0.9, 0.15)}};

// Query points: far (several triangle sizes away, both sides), near the
// interior (1e-2 above and below the plane), near an edge and near a vertex
// (off the plane), and beside the triangle in its plane's neighbourhood.
std::vector<Vec3> Queries() {
  const Vec3 c = (kTri.v[0] + kTri.v[1] + kTri.v[2]) / 3.0;
  const Vec3 n = (kTri.v[1] - kTri.v[0]).cross(kTri.v[2] - kTri.v[0]).normalized();
  const Vec3 mid01 = 0.5 * (kTri.v[0] + kTri.v[1]);
  return {c + 5.0 * n + Vec3(0.3, -0.2, 0.1),  // far, front
          c - 4.0 * n + Vec3(-1.0, 2.0, 0.5),  // far, back
          Vec3(6.0, 5.0, -3.0),                // far, oblique
          c + 0.01 * n,                        // near the interior, front
          c - 0.01 * n + Vec3(0.05, 0.02, 0),  // near the interior, back
          mid01 + 0.02 * n + Vec3(0, -0.01, 0),  // near an edge
          kTri.v[2] + Vec3(0.01, 0.015, -0.02),  // near a vertex
          c + Vec3(1.5, 0.0, 0.2)};              // beside, about the triangle's size away
}

TEST(GradientTest, SolidAngleValueMatchesTheExactKernel) {
  for (const Vec3& q : Queries())
    EXPECT_NEAR(SolidAngleTermGrad(kTri.v[0], kTri.v[1], kTri.v[2], q, nullptr),
                TriangleSolidAngleOver4Pi(kTri.v[0], kTri.v[1], kTri.v[2], q), 1e-14);
}

TEST(GradientTest, PerTriangleDerivativesMatchCentralDifferences) {
  for (WindingForm form : {WindingForm::kSolidAngle, WindingForm::kNaive}) {
    int qi = 0;
    for (const Vec3& q : Queries()) {
      Vec3 an[3], fd[3];
      WindingTermGrad(form, kTri.v[0], kTri.v[1], kTri.v[2], q, an);
      FdTermGrad(form, kTri, q, 1e-7, fd);
      EXPECT_LT(RelErr(fd, an), kRelTol) << WindingFormName(form) << " query " << qi << " |g| "
                                         << an[0].norm() + an[1].norm() + an[2].norm();
      // Translation invariance: ∂/∂q = -Σ_j ∂/∂v_j; moving the triangle and q
      // together changes nothing, checked against a difference in q.
      const double h = 1e-7;
      for (int k = 0; k < 3; ++k) {
        Vec3 qp = q, qm = q;
        qp[k] += h;
        qm[k] -= h;
        const double dq = (WindingTermGrad(form, kTri.v[0], kTri.v[1], kTri.v[2], qp, nullptr) -
                           WindingTermGrad(form, kTri.v[0], kTri.v[1], kTri.v[2], qm, nullptr)) /
                          (2 * h);
        const double sum = an[0][k] + an[1][k] + an[2][k];
        EXPECT_NEAR(dq, -sum, kRelTol * (std::abs(sum) + an[0].norm()));
      }
      ++qi;
    }
  }
}

TEST(GradientTest, SoftenedNaiveDerivativesMatchCentralDifferences) {
  for (double eps : {0.01, 0.1}) {
    int qi = 0;
    for (const Vec3& q : Queries()) {
      Vec3 an[3], fd[3];
      NaiveTermGrad(kTri.v[0], kTri.v[1], kTri.v[2], q, an, eps);
      const double h = 1e-7;
      for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k) {
          Tri p = kTri, m = kTri;
          p.v[j][k] += h;
          m.v[j][k] -= h;
          fd[j][k] = (NaiveTermGrad(p.v[0], p.v[1], p.v[2], q, nullptr, eps) -
                      NaiveTermGrad(m.v[0], m.v[1], m.v[2], q, nullptr, eps)) / (2 * h);
        }
      EXPECT_LT(RelErr(fd, an), kRelTol) << "eps " << eps << " query " << qi++;
    }
  }
}

TEST(GradientTest, SofteningBoundsTheNaiveWindingNumberNearTheSurface) {
  // eq. 4 blows up like Δ/d² at nodes a small distance d above a face; the
  // softened kernel keeps w a soft step in about [0, 1]; far away both agree
  // with the exact winding number.
  const Mesh m = MakeIcosphere(0.5, 3);
  const Vec3 a = m.V.row(m.F(0, 0)), b = m.V.row(m.F(0, 1)), c = m.V.row(m.F(0, 2));
  const Vec3 n = (b - a).cross(c - a).normalized(), cen = (a + b + c) / 3.0;
  MatrixX3d Q(4, 3);
  Q.row(0) = (cen + 0.001 * n).transpose();  // just outside
  Q.row(1) = (cen - 0.001 * n).transpose();  // just inside
  Q << Q.row(0), Q.row(1), 0.05, 0.02, -0.01, 1.5, 0.2, 0.1;
  const VectorXd w0 = WindingNumbers(m, Q, WindingForm::kNaive, 0.0);
  const VectorXd we = WindingNumbers(m, Q, WindingForm::kNaive, 0.03);
  const VectorXd wx = WindingNumbers(m, Q, WindingForm::kSolidAngle);
  EXPECT_GT(std::max(std::abs(w0[0]), std::abs(w0[1] - 1.0)), 1.0);  // eq. 4 is far off here
  for (int i = 0; i < 2; ++i) {
    EXPECT_GT(we[i], 0.2) << i;  // a soft step around 1/2
    EXPECT_LT(we[i], 0.8) << i;
  }
  EXPECT_NEAR(we[2], 1.0, 0.02);
  EXPECT_NEAR(we[3], 0.0, 0.02);
  EXPECT_NEAR(w0[2], wx[2], 0.02);
  EXPECT_NEAR(w0[3], wx[3], 0.02);
}

TEST(GradientTest, NaiveTermIsTheCentroidQuadratureFarAway) {
  // Far from the triangle the solid angle tends to the eq. 4 dipole term
  // (relative difference O((size / distance)²)).
  const Vec3 n = (kTri.v[1] - kTri.v[0]).cross(kTri.v[2] - kTri.v[0]).normalized();
  const Vec3 c = (kTri.v[0] + kTri.v[1] + kTri.v[2]) / 3.0;
  for (double d : {10.0, 100.0}) {
    const Vec3 q = c + d * (n + Vec3(0.2, 0.1, 0.0)).normalized();
    const double exact = SolidAngleTermGrad(kTri.v[0], kTri.v[1], kTri.v[2], q, nullptr);
    const double naive = NaiveTermGrad(kTri.v[0], kTri.v[1], kTri.v[2], q, nullptr);
    EXPECT_NEAR(naive / exact, 1.0, 2.0 / (d * d));
  }
}

TEST(GradientTest, ExactFormGradientVanishesForAClosedMesh) {
  // The paper's "gradients vanishing" (§2.4): the Alg. 1 winding number of a
  // closed mesh is constant in the vertices away from the surface, so the
  // per-face derivatives cancel at every vertex; eq. 4's do not.
  const Mesh m = MakeIcosphere(0.5, 2);
  MatrixX3d Q(3, 3);
  Q << 0.1, 0.05, -0.02,  // inside
      0.9, 0.3, 0.1,      // outside
      0.3, 0.3, 0.3;      // outside, near the surface (|q| ≈ 0.52)
  for (int i = 0; i < Q.rows(); ++i) {
    VectorXd lam = VectorXd::Zero(Q.rows());
    lam[i] = 1.0;
    const MatrixX3d ge = WindingNumberVjp(m, Q, lam, WindingForm::kSolidAngle);
    const MatrixX3d gn = WindingNumberVjp(m, Q, lam, WindingForm::kNaive);
    // Magnitude of a single face's derivative at this query, for scale.
    Vec3 g[3];
    double face_scale = 0;
    for (int f = 0; f < m.NumFaces(); ++f) {
      SolidAngleTermGrad(m.V.row(m.F(f, 0)), m.V.row(m.F(f, 1)), m.V.row(m.F(f, 2)), Q.row(i).transpose(), g);
      face_scale = std::max(face_scale, g[0].norm());
    }
    EXPECT_LT(ge.cwiseAbs().maxCoeff(), 1e-10 * face_scale) << "query " << i;
    EXPECT_GT(gn.cwiseAbs().maxCoeff(), 1e-3 * face_scale) << "query " << i;
  }
}

// A small perturbed icosphere (42 vertices), a 6³ grid around it and the
// occupancy of an ellipsoid as target.
struct LossCase {
  Mesh mesh;
  MatrixX3d Q;
  VectorXd target;
};

LossCase MakeLossCase() {
  LossCase c;
  c.mesh = MakeIcosphere(0.4, 1);
  Rng rng(7);
  for (int i = 0; i < c.mesh.NumVertices(); ++i)
    for (int k = 0; k < 3; ++k) c.mesh.V(i, k) += 0.03 * rng.Normal();
  const int n = 6;
  c.Q.resize(n * n * n, 3);
  c.target.resize(n * n * n);
  int idx = 0;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i, ++idx) {
        const Vec3 p(-0.6 + 1.2 * i / (n - 1) + 0.013, -0.6 + 1.2 * j / (n - 1) - 0.007, -0.6 + 1.2 * k / (n - 1));
        c.Q.row(idx) = p.transpose();
        c.target[idx] = (p.x() * p.x() / 0.25 + p.y() * p.y() / 0.09 + p.z() * p.z() / 0.16) < 1.0 ? 1.0 : 0.0;
      }
  return c;
}

TEST(GradientTest, LossGradientMatchesCentralDifferencesOnAnIcosphere) {
  const LossCase c = MakeLossCase();
  struct Setting {
    WindingForm form;
    OccupancyMap map;
    OccupancyLossKind loss;
    double softening = 0.0;
  };
  for (const Setting s : {Setting{WindingForm::kNaive, OccupancyMap::kIdentity, OccupancyLossKind::kMse},
                          Setting{WindingForm::kSolidAngle, OccupancyMap::kIdentity, OccupancyLossKind::kMse},
                          Setting{WindingForm::kNaive, OccupancyMap::kSigmoid, OccupancyLossKind::kBce},
                          Setting{WindingForm::kNaive, OccupancyMap::kIdentity, OccupancyLossKind::kMse, 0.05},
                          Setting{WindingForm::kSolidAngle, OccupancyMap::kSigmoid, OccupancyLossKind::kMse}}) {
    // The Alg. 1 gradient of a closed mesh vanishes (test above): check it on
    // an open mesh (the cap z > 0.25 removed), where w is not a step function.
    Mesh mesh = c.mesh;
    if (s.form == WindingForm::kSolidAngle) {
      std::vector<int> keep;
      for (int f = 0; f < mesh.NumFaces(); ++f)
        if ((mesh.V(mesh.F(f, 0), 2) + mesh.V(mesh.F(f, 1), 2) + mesh.V(mesh.F(f, 2), 2)) / 3.0 < 0.25)
          keep.push_back(f);
      MatrixX3i F(keep.size(), 3);
      for (size_t i = 0; i < keep.size(); ++i) F.row(i) = c.mesh.F.row(keep[i]);
      ASSERT_LT(F.rows(), c.mesh.NumFaces());
      mesh.F = F;
    }
    OccupancyLossOptions o;
    o.occupancy.form = s.form;
    o.occupancy.map = s.map;
    o.occupancy.sharpness = 4.0;
    o.occupancy.softening = s.softening;
    o.loss = s.loss;
    const OccupancyLossResult r = OccupancyLoss(mesh, c.Q, c.target, o);
    ASSERT_EQ(r.grad.rows(), mesh.NumVertices());
    MatrixX3d fd(mesh.NumVertices(), 3);
    const double h = 1e-6;
    for (int i = 0; i < mesh.NumVertices(); ++i)
      for (int k = 0; k < 3; ++k) {
        Mesh p = mesh, m = mesh;
        p.V(i, k) += h;
        m.V(i, k) -= h;
        fd(i, k) = (OccupancyLoss(p, c.Q, c.target, o).loss - OccupancyLoss(m, c.Q, c.target, o).loss) / (2 * h);
      }
    const double rel = (fd - r.grad).norm() / r.grad.norm();
    // Loss values are O(1) sums of smooth terms; h = 1e-6 gives round-off
    // ≈ 1e-16 / 1e-6 = 1e-10 absolute on gradients of norm ≳ 1e-3 here.
    EXPECT_LT(rel, kRelTol) << WindingFormName(s.form) << " " << OccupancyMapName(s.map) << " "
                            << OccupancyLossName(s.loss) << " |grad| " << r.grad.norm();
    EXPECT_GT(r.grad.norm(), 1e-4);
  }
}

TEST(GradientTest, SameBitsAtOneAndTwoThreads) {
  const LossCase c = MakeLossCase();
  for (WindingForm form : {WindingForm::kNaive, WindingForm::kSolidAngle}) {
    OccupancyLossOptions o;
    o.occupancy.form = form;
    OccupancyLossResult r1, r2;
    {
      ThreadLimit l(1);
      r1 = OccupancyLoss(c.mesh, c.Q, c.target, o);
    }
    {
      ThreadLimit l(2);
      r2 = OccupancyLoss(c.mesh, c.Q, c.target, o);
    }
    EXPECT_EQ(r1.loss, r2.loss);
    EXPECT_TRUE((r1.grad.array() == r2.grad.array()).all()) << WindingFormName(form);
  }
}

TEST(GradientTest, OccupancyMapsAndLossTermsHaveTheirDerivatives) {
  for (OccupancyMap map : {OccupancyMap::kIdentity, OccupancyMap::kClamp, OccupancyMap::kSigmoid}) {
    SoftOccupancyOptions o;
    o.map = map;
    o.sharpness = 7.0;
    for (double w : {-0.3, 0.2, 0.5, 0.77, 1.4}) {
      double d = 0;
      OccupancyFromWinding(w, o, &d);
      const double h = 1e-7;
      const double fd = (OccupancyFromWinding(w + h, o, nullptr) - OccupancyFromWinding(w - h, o, nullptr)) / (2 * h);
      EXPECT_NEAR(d, fd, 1e-6) << OccupancyMapName(map) << " w=" << w;
    }
  }
  EXPECT_EQ(OccupancyFromWinding(0.3, {}, nullptr), 0.3);  // the paper: occupancy = w
  for (OccupancyLossKind k : {OccupancyLossKind::kMse, OccupancyLossKind::kBce})
    for (double t : {0.0, 1.0})
      for (double o : {0.1, 0.6, 0.95}) {
        double d = 0;
        OccupancyLossTerm(o, t, k, &d);
        const double h = 1e-7;
        EXPECT_NEAR(d, (OccupancyLossTerm(o + h, t, k, nullptr) - OccupancyLossTerm(o - h, t, k, nullptr)) / (2 * h),
                    1e-5 * (1 + std::abs(d)));
      }
}

TEST(GradientTest, BadInputIsAClearError) {
  const LossCase c = MakeLossCase();
  EXPECT_THROW(OccupancyLoss(c.mesh, c.Q, VectorXd::Zero(3), {}), Error);
  EXPECT_THROW(WindingNumberVjp(c.mesh, c.Q, VectorXd::Zero(2), WindingForm::kNaive), Error);
  Mesh bad = c.mesh;
  bad.F(0, 0) = 999;
  EXPECT_THROW(WindingNumbers(bad, c.Q, WindingForm::kNaive), InputError);
  SoftOccupancyOptions so;
  so.sharpness = 0;
  EXPECT_THROW(so.Check(), OptionError);
  EXPECT_THROW(ParseWindingForm("atan"), OptionError);
  // Degenerate pairs contribute zero, not NaN: q on a vertex, q at a centroid.
  Vec3 g[3];
  EXPECT_EQ(SolidAngleTermGrad(kTri.v[0], kTri.v[1], kTri.v[2], kTri.v[0], g), 0.0);
  EXPECT_TRUE(g[0].allFinite() && g[1].allFinite() && g[2].allFinite());
  const Vec3 cen = (kTri.v[0] + kTri.v[1] + kTri.v[2]) / 3.0;
  EXPECT_EQ(NaiveTermGrad(kTri.v[0], kTri.v[1], kTri.v[2], cen, g), 0.0);
  EXPECT_TRUE(g[0].allFinite());
}

}  // namespace
}  // namespace arcs
