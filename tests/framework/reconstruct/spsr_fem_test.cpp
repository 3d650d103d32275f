// The screened Poisson's finite elements (spsr_fem.h) against the identities
// they must satisfy: the Neumann stiffness annihilates constants and is
// symmetric, the class stencils are the assembled operator's rows, trilinear
// weights reproduce linear functions, prolongation is exact on them, the
// restriction is its transpose, and a coarse grid's screening is the
// samples' rank-one terms.
#include "framework/reconstruct/spsr_fem.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace arcs::spsr_fem {
namespace {

// The tent of node a on [0, 1] (h = 1 / res) and its derivative.
double Tent(int a, int res, double x) { return std::max(0.0, 1.0 - std::abs(x * res - a)); }
double TentSlope(int a, int res, double x) {
  const double u = x * res - a;
  if (u <= -1.0 || u >= 1.0) return 0.0;
  return u < 0 ? res : -res;
}

TEST(SpsrFem, TentIntegralsAreTheQuadratureOfTheTents) {
  // Simpson's rule on each cell is exact for the products (at most
  // quadratic there); the slopes are read at interior points of the cell.
  for (int res : {2, 4, 8}) {
    const Tent1D t{1.0 / res, res};
    for (int a = 0; a <= res; ++a)
      for (int o = -1; o <= 1; ++o) {
        const int b = a + o;
        if (b < 0 || b > res) continue;
        double m = 0, s = 0, d = 0;
        for (int k = 0; k < res; ++k) {
          const double x0 = double(k) / res, x1 = double(k + 1) / res, xm = 0.5 * (x0 + x1), h = x1 - x0;
          auto simpson = [&](auto&& f) { return h / 6.0 * (f(x0) + 4.0 * f(xm) + f(x1)); };
          m += simpson([&](double x) { return Tent(a, res, x) * Tent(b, res, x); });
          const double sa = TentSlope(a, res, xm), sb = TentSlope(b, res, xm);
          s += h * sa * sb;
          d += sa * simpson([&](double x) { return Tent(b, res, x); });
        }
        EXPECT_NEAR(t.M(a, o), m, 1e-14) << res << " " << a << " " << o;
        EXPECT_NEAR(t.S(a, o), s, 1e-12 * res) << res << " " << a << " " << o;
        EXPECT_NEAR(t.D(a, o), d, 1e-14) << res << " " << a << " " << o;
      }
  }
}

TEST(SpsrFem, StiffnessStencilsAnnihilateConstantsAndAreSymmetric) {
  for (int res : {4, 8, 32}) {
    const Tent1D t{1.0 / res, res};
    const ClassStencil k = StencilByClass(t);
    for (int c = 0; c < 27; ++c) {
      const int cl[3] = {c % 3, (c / 3) % 3, c / 9};
      double sum = 0, scale = 0;
      for (int o = 0; o < 27; ++o) {
        // Offsets that leave the cube (below the low face, above the high
        // one) have no neighbour there: only existing ones are summed.
        const int off[3] = {Ox(o), Oy(o), Oz(o)};
        bool inside = true;
        for (int a = 0; a < 3; ++a) inside = inside && !(cl[a] == 0 && off[a] < 0) && !(cl[a] == 2 && off[a] > 0);
        if (!inside) continue;
        sum += k[c][o];
        scale += std::abs(k[c][o]);
      }
      EXPECT_NEAR(sum, 0.0, 1e-12 * scale) << "res " << res << " class " << c;
      EXPECT_GT(k[c][13], 0.0);
    }
    // Interior: K(i, i + o) = K(i + o, i), i.e. the stencil is point-symmetric.
    for (int o = 0; o < 27; ++o) EXPECT_EQ(k[13][o], k[13][26 - o]) << o;
  }
}

TEST(SpsrFem, CoarseGridRowsAreTheClassStencils) {
  CoarseGrid g;
  const std::vector<Vec3> none;
  g.Build(2, none, nullptr, nullptr, 0.0);
  ASSERT_EQ(g.res, 4);
  const ClassStencil k = StencilByClass(Tent1D{1.0 / g.res, g.res});
  for (int z = 0; z <= g.res; ++z)
    for (int y = 0; y <= g.res; ++y)
      for (int x = 0; x <= g.res; ++x) {
        const int c = NodeClass(x, y, z, g.res);
        for (int o = 0; o < 27; ++o) {
          const int a = x + Ox(o), b = y + Oy(o), e = z + Oz(o);
          const bool in = a >= 0 && b >= 0 && e >= 0 && a <= g.res && b <= g.res && e <= g.res;
          const double expected = in ? k[c][o] : 0.0;
          EXPECT_EQ(g.coef[static_cast<std::size_t>(g.Idx(x, y, z)) * 27 + o], expected) << x << y << z << " " << o;
        }
      }
  // The constant vector is in the unscreened operator's null space.
  std::vector<double> one(g.N(), 1.0), out;
  g.Apply(one, out);
  for (double v : out) EXPECT_NEAR(v, 0.0, 1e-12);
}

TEST(SpsrFem, TrilinearWeightsReproduceLinearFunctions) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int res : {1, 4, 32}) {
    for (int rep = 0; rep < 50; ++rep) {
      const Vec3 p(u(rng), u(rng), u(rng));
      int c[3];
      double w[8];
      CellOf(p, res, c, w);
      double sum = 0;
      Vec3 at = Vec3::Zero();
      for (int q = 0; q < 8; ++q) {
        EXPECT_GE(w[q], 0.0);
        sum += w[q];
        at += w[q] * Vec3(c[0] + (q & 1), c[1] + ((q >> 1) & 1), c[2] + ((q >> 2) & 1)) / res;
      }
      EXPECT_NEAR(sum, 1.0, 1e-14);
      EXPECT_NEAR((at - p).norm(), 0.0, 1e-14);
    }
  }
  // The cube's far faces belong to the last cell.
  int c[3];
  double w[8];
  CellOf(Vec3(1, 1, 1), 8, c, w);
  EXPECT_EQ(c[0], 7);
  EXPECT_DOUBLE_EQ(w[7], 1.0);
}

TEST(SpsrFem, ProlongationIsExactOnLinearFunctionsAndRestrictionIsItsTranspose) {
  const int r = 4, f1 = 2 * r + 1, c1 = r + 1;
  auto lin = [](double x, double y, double z) { return 0.3 + 1.5 * x - 2.0 * y + 0.25 * z; };
  std::vector<double> coarse(static_cast<std::size_t>(c1) * c1 * c1), fine(static_cast<std::size_t>(f1) * f1 * f1, 0.0);
  for (int z = 0; z < c1; ++z)
    for (int y = 0; y < c1; ++y)
      for (int x = 0; x < c1; ++x) coarse[x + c1 * (y + c1 * z)] = lin(x / double(r), y / double(r), z / double(r));
  ProlongAdd(r, coarse, fine);
  for (int z = 0; z < f1; ++z)
    for (int y = 0; y < f1; ++y)
      for (int x = 0; x < f1; ++x)
        EXPECT_NEAR(fine[x + f1 * (y + f1 * z)], lin(x / (2.0 * r), y / (2.0 * r), z / (2.0 * r)), 1e-13);

  // <R f, c> = <f, P c> for any f and c.
  std::mt19937 rng(3);
  std::normal_distribution<double> n01;
  std::vector<double> f(fine.size()), c(coarse.size()), rf, pc(fine.size(), 0.0);
  for (double& v : f) v = n01(rng);
  for (double& v : c) v = n01(rng);
  Restrict(r, f, rf);
  ProlongAdd(r, c, pc);
  double lhs = 0, rhs = 0;
  for (std::size_t i = 0; i < c.size(); ++i) lhs += rf[i] * c[i];
  for (std::size_t i = 0; i < f.size(); ++i) rhs += f[i] * pc[i];
  EXPECT_NEAR(lhs, rhs, 1e-10 * (std::abs(lhs) + 1.0));
}

TEST(SpsrFem, CoarseGridScreeningAddsEachSamplesRankOneTerm) {
  // Two samples, one of them counted three times: the screened operator
  // minus the unscreened one is beta * sum_s count_s w_s w_s^T.
  const std::vector<Vec3> pts = {Vec3(0.3, 0.55, 0.71), Vec3(0.9, 0.12, 0.4)};
  const std::vector<double> count = {1.0, 3.0};
  const double beta = 2.5;
  CoarseGrid plain, screened;
  plain.Build(2, pts, nullptr, nullptr, 0.0);
  screened.Build(2, pts, nullptr, &count, beta);
  std::mt19937 rng(11);
  std::normal_distribution<double> n01;
  std::vector<double> v(plain.N()), a, b;
  for (double& x : v) x = n01(rng);
  plain.Apply(v, a);
  screened.Apply(v, b);
  std::vector<double> expected(a);
  for (std::size_t s = 0; s < pts.size(); ++s) {
    int c[3];
    double w[8];
    CellOf(pts[s], plain.res, c, w);
    double value = 0;  // the sample's interpolated value of v
    for (int q = 0; q < 8; ++q) value += w[q] * v[plain.Idx(c[0] + (q & 1), c[1] + ((q >> 1) & 1), c[2] + ((q >> 2) & 1))];
    for (int q = 0; q < 8; ++q)
      expected[plain.Idx(c[0] + (q & 1), c[1] + ((q >> 1) & 1), c[2] + ((q >> 2) & 1))] += beta * count[s] * w[q] * value;
  }
  for (int i = 0; i < plain.N(); ++i) EXPECT_NEAR(b[i], expected[i], 1e-12 * (1.0 + std::abs(expected[i]))) << i;
  // Indexed samples (idx) read the same points.
  CoarseGrid by_index;
  const std::vector<int> idx = {1};
  by_index.Build(2, pts, &idx, nullptr, beta);
  CoarseGrid only_second;
  only_second.Build(2, std::vector<Vec3>{pts[1]}, nullptr, nullptr, beta);
  EXPECT_EQ(by_index.coef, only_second.coef);
}

}  // namespace
}  // namespace arcs::spsr_fem
