#include "framework/rfta/arc_projector.h"

#include "framework/error.h"
#include "framework/rfta/free_space.h"
#include "framework/util/parallel.h"
#include "tests/framework/rfta/rfta_test_shapes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <vector>

namespace arcs {
namespace {

using rfta_test::BallSdfGrid;

struct Checked {
  double max_surface_error = 0.0;   // max | |x - center| - R |
  double mean_surface_error = 0.0;
  double min_normal_dot = 1.0;      // min n . (x - center)/|x - center|
  double mean_normal_dot = 0.0;
};

// Checks the invariants of an arc projection of the ball SDF (radius R):
// every point on its sample's sphere, feasible against all spheres of its
// sign (no batching below 10^4 samples), unit normals; returns the errors
// against the true surface.
Checked CheckProjection(const SdfSamples& s, const ArcProjection& a, double R, double tol_unit) {
  const double scale = ComputeUnitFrame(s).scale;
  const double tol = tol_unit * scale;
  Checked c;
  EXPECT_EQ(a.points.P.rows(), a.points.N.rows());
  EXPECT_EQ(static_cast<std::int64_t>(a.sample.size()), a.points.P.rows());
  EXPECT_TRUE(std::is_sorted(a.sample.begin(), a.sample.end()));
  for (int t = 0; t < a.points.Size(); ++t) {
    const int i = a.sample[t];
    const Vec3 x = a.points.P.row(t).transpose();
    const Vec3 n = a.points.N.row(t).transpose();
    const Vec3 p = SamplePoint(s, i);
    EXPECT_NEAR((x - p).norm(), std::abs(s.values[i]), 1e-9) << "point " << t;
    EXPECT_NEAR(n.norm(), 1.0, 1e-12);
    // Feasible: no other sphere of the same sign contains x by more than tol.
    for (std::int64_t j = 0; j < s.Size(); ++j) {
      if (j == i || (s.values[j] > 0) != (s.values[i] > 0)) continue;
      const double depth = std::abs(s.values[j]) - (x - SamplePoint(s, j)).norm();
      EXPECT_LE(depth, tol * (1 + 1e-9)) << "point of sample " << i << " inside sphere " << j;
    }
    // Eq. (2) by hand: n = sign(s) (p - x) / |p - x|.
    EXPECT_LT((n - (s.values[i] > 0 ? 1.0 : -1.0) * (p - x).normalized()).norm(), 1e-12);
    const double e = std::abs(x.norm() - R);
    c.max_surface_error = std::max(c.max_surface_error, e);
    c.mean_surface_error += e / a.points.Size();
    const double dot = n.dot(x.normalized());
    c.min_normal_dot = std::min(c.min_normal_dot, dot);
    c.mean_normal_dot += dot / a.points.Size();
  }
  return c;
}

TEST(ArcProjector, BallGridInvariants3D) {
  for (int n : {10, 20}) {
    const double R = 0.3, h = 1.0 / n;  // grid spacing
    const SdfSamples s = BallSdfGrid(n, R);
    Context ctx(1);
    const FreeSpaceSamples f = RasterizeFreeSpace(s, RasterizeOptions(), ctx);
    const ArcProjection a = ProjectToArcs(s, f, ArcProjectorOptions(), ctx);
    // Every sphere but the exact zeros (grid nodes on the surface) wants a
    // point, and the ball's spheres all have a non-empty arc.
    std::int64_t zeros = 0;
    for (std::int64_t i = 0; i < s.Size(); ++i) zeros += std::abs(s.values[i]) <= 1e-12;
    EXPECT_EQ(a.stats.zero, zeros);
    EXPECT_EQ(a.stats.spheres, s.Size() - zeros);
    EXPECT_EQ(a.stats.dropped, 0) << "n " << n;
    EXPECT_EQ(a.points.Size(), a.stats.spheres - a.stats.dropped);
    EXPECT_GT(a.stats.made_feasible, 0);  // the projection alone is not always feasible
    const Checked c = CheckProjection(s, a, R, 1e-4);
    // Tangency points of exact SDF spheres lie on the surface up to the arc's
    // extent: far below the grid spacing.
    EXPECT_LT(c.mean_surface_error, 0.02 * h) << "n " << n;
    EXPECT_LT(c.max_surface_error, 0.5 * h) << "n " << n;
    EXPECT_GT(c.min_normal_dot, 0.0) << "n " << n;  // outward, every one
    EXPECT_GT(c.mean_normal_dot, 0.98) << "n " << n;  // measured 0.989 at n = 10
  }
}

// The official candidate rule keeps only feasible points too (it may drop
// more spheres: it can cycle between pairs).
TEST(ArcProjector, PairChoiceFirstKeepsFeasiblePoints) {
  const SdfSamples s = BallSdfGrid(12, 0.27);
  Context ctx(2);
  const FreeSpaceSamples f = RasterizeFreeSpace(s, RasterizeOptions(), ctx);
  ArcProjectorOptions o;
  o.search.pair_choice = PairChoice::kFirst;
  const ArcProjection a = ProjectToArcs(s, f, o, ctx);
  EXPECT_LE(a.stats.dropped, s.Size() / 20);
  const Checked c = CheckProjection(s, a, 0.27, 1e-4);
  EXPECT_GT(c.min_normal_dot, 0.0);
  EXPECT_LT(c.mean_surface_error, 0.02 / 12);
}

TEST(ArcProjector, Disc2D) {
  const double R = 0.31;
  const SdfSamples s = BallSdfGrid(40, R, 2);
  Context ctx(4);
  const FreeSpaceSamples f = RasterizeFreeSpace(s, RasterizeOptions(), ctx);
  const ArcProjection a = ProjectToArcs(s, f, ArcProjectorOptions(), ctx);
  EXPECT_LE(a.stats.dropped, s.Size() / 100);
  const Checked c = CheckProjection(s, a, R, 1e-4);
  EXPECT_LT(c.mean_surface_error, 0.02 / 40);
  EXPECT_GT(c.min_normal_dot, 0.0);
  for (int t = 0; t < a.points.Size(); ++t) {
    EXPECT_EQ(a.points.P(t, 2), 0.0);
    EXPECT_EQ(a.points.N(t, 2), 0.0);
  }
}

TEST(ArcProjector, DeterministicAcrossThreadsAndBatched) {
  const SdfSamples s = BallSdfGrid(24, 0.3);  // 15625 samples > batch 10000
  Context ctx(5);
  const FreeSpaceSamples f = RasterizeFreeSpace(s, RasterizeOptions(), ctx);
  ArcProjectorOptions o;
  o.batch_size = 3000;
  ArcProjection a, b;
  {
    ThreadLimit one(1);
    a = ProjectToArcs(s, f, o, ctx);
  }
  {
    ThreadLimit two(2);
    b = ProjectToArcs(s, f, o, ctx);
  }
  EXPECT_EQ(a.points.P, b.points.P);
  EXPECT_EQ(a.points.N, b.points.N);
  EXPECT_EQ(a.sample, b.sample);
  // Both signs were batched to at most 3000 constraint spheres.
  std::int64_t negatives = 0;
  for (std::int64_t i = 0; i < s.Size(); ++i) negatives += s.values[i] < -1e-12;
  ASSERT_GT(s.Size() - negatives, 3000);
  EXPECT_EQ(a.stats.batch[0], 3000);
  EXPECT_EQ(a.stats.batch[1], std::min<std::int64_t>(3000, negatives));
  // Batched points still lie on their spheres with outward normals (except
  // on tiny spheres, |s| < h/50, whose few-tol arcs the sparse batch barely
  // constrains: their direction is nearly free).
  double mean_dot = 0.0;
  for (int t = 0; t < a.points.Size(); ++t) {
    const Vec3 x = a.points.P.row(t).transpose();
    const double r = std::abs(s.values[a.sample[t]]);
    EXPECT_NEAR((x - SamplePoint(s, a.sample[t])).norm(), r, 1e-9);
    const double dot = a.points.N.row(t).dot(x.normalized());
    if (r > 1.0 / 24 / 50) {
      EXPECT_GT(dot, 0.0);
    }
    mean_dot += dot / a.points.Size();
  }
  EXPECT_GT(mean_dot, 0.99);
}

TEST(ArcProjector, SkipsZeroAndClampedSamples) {
  SdfSamples s = BallSdfGrid(10, 0.3);
  // A sample exactly on the surface, and a clamped SDF.
  s.values[0] = 0.0;
  s.clamp = 0.2;
  for (std::int64_t i = 0; i < s.Size(); ++i) s.values[i] = std::clamp(s.values[i], -0.2, 0.2);
  Context ctx(6);
  const FreeSpaceSamples f = RasterizeFreeSpace(s, RasterizeOptions(), ctx);
  const ArcProjection a = ProjectToArcs(s, f, ArcProjectorOptions(), ctx);
  std::int64_t zeros = 0;
  for (std::int64_t i = 0; i < s.Size(); ++i) zeros += std::abs(s.values[i]) <= 1e-12;
  EXPECT_GE(zeros, 1);
  EXPECT_EQ(a.stats.zero, zeros);
  std::int64_t clamped = 0;
  for (std::int64_t i = 0; i < s.Size(); ++i) clamped += std::abs(s.values[i]) >= 0.2;
  EXPECT_EQ(a.stats.clamped, clamped);
  EXPECT_GT(clamped, 100);
  for (int i : a.sample) {
    EXPECT_NE(i, 0);
    EXPECT_LT(std::abs(s.values[i]), 0.2);
    EXPECT_GT(std::abs(s.values[i]), 1e-12);
  }
  EXPECT_EQ(a.stats.spheres, s.Size() - zeros - clamped);
}

TEST(ArcProjector, FreePointsWithoutSignsServeBoth) {
  const SdfSamples s = BallSdfGrid(10, 0.3);
  Context ctx(7);
  FreeSpaceSamples f = RasterizeFreeSpace(s, RasterizeOptions(), ctx);
  f.sign.clear();
  const ArcProjection a = ProjectToArcs(s, f, ArcProjectorOptions(), ctx);
  const Checked c = CheckProjection(s, a, 0.3, 1e-4);
  EXPECT_GT(c.min_normal_dot, 0.0);
}

TEST(ArcProjector, BadInputsThrow) {
  const SdfSamples s = BallSdfGrid(6, 0.3);
  Context ctx;
  const FreeSpaceSamples f = RasterizeFreeSpace(s, RasterizeOptions(), ctx);
  SdfSamples pos = s;
  pos.values = pos.values.cwiseAbs().array() + 0.01;
  EXPECT_THROW(ProjectToArcs(pos, f, ArcProjectorOptions(), ctx), Error);
  SdfSamples neg = s;
  neg.values = -(neg.values.cwiseAbs().array() + 0.01);
  EXPECT_THROW(ProjectToArcs(neg, f, ArcProjectorOptions(), ctx), Error);
  SdfSamples nan = s;
  nan.values[3] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(ProjectToArcs(nan, f, ArcProjectorOptions(), ctx), Error);
  SdfSamples one;
  one.points = MatrixXd::Constant(1, 3, 0.1);
  one.values = VectorXd::Constant(1, 0.2);
  EXPECT_THROW(ProjectToArcs(one, f, ArcProjectorOptions(), ctx), Error);
  // Free points for one sign only (a thin shape on a coarse grid): that
  // sign's spheres start without points, with a warning; none at all: error.
  FreeSpaceSamples only_pos = f;
  for (auto& v : only_pos.sign) v = 1;
  std::vector<std::string> warnings;
  Context warn_ctx;
  warn_ctx.set_log([&](LogLevel, const std::string& m) { warnings.push_back(m); });
  const ArcProjection half = ProjectToArcs(s, only_pos, ArcProjectorOptions(), warn_ctx);
  ASSERT_GT(half.points.Size(), 0);
  for (int i : half.sample) EXPECT_GT(s.values[i], 0.0) << "only positive spheres can have points";
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("negative"), std::string::npos) << warnings[0];
  FreeSpaceSamples no_free;
  EXPECT_THROW(ProjectToArcs(s, no_free, ArcProjectorOptions(), ctx), Error);
  FreeSpaceSamples bad_signs = f;
  bad_signs.sign.pop_back();
  EXPECT_THROW(ProjectToArcs(s, bad_signs, ArcProjectorOptions(), ctx), Error);
  ArcProjectorOptions o;
  o.search.tol = -1.0;
  EXPECT_THROW(ProjectToArcs(s, f, o, ctx), OptionError);
}

// Algorithm 2 on hand-made spheres: a point inside two neighbours moves to
// the sphere's feasible region and stays on the sphere.
TEST(MakeFeasible, TwoAndThreeSphereConfigurations) {
  MatrixX3d C(4, 3);
  C << 0.5, 0.5, 0.5,   // sphere 0: the one we move on
      0.7, 0.5, 0.5,    // neighbours overlapping it
      0.5, 0.7, 0.5,
      0.35, 0.35, 0.5;
  VectorXd R(4);
  R << 0.15, 0.2, 0.2, 0.1;
  const std::vector<int> ids = {0, 1, 2, 3};
  const SphereTree tree(C, R, ids);
  const Vec3 c = C.row(0).transpose();
  MakeFeasibleOptions o;
  o.k_search = 8;
  // Start inside spheres 1 and 2 (towards +x+y).
  Vec3 x = c + 0.15 * Vec3(1, 1, 0).normalized();
  int steps = 0;
  ASSERT_TRUE(tree.AnyContains(x, -o.tol, 0));
  EXPECT_TRUE(MakeFeasible(tree, c, 0.15, 0, o, &x, &steps));
  EXPECT_GE(steps, 1);
  EXPECT_NEAR((x - c).norm(), 0.15, 1e-12);
  EXPECT_FALSE(tree.AnyContains(x, -o.tol, 0));
  for (int j = 1; j < 4; ++j) EXPECT_GE((x - Vec3(C.row(j).transpose())).norm(), R[j] - o.tol);
  // What the caller knows of the first test, at the projected start point,
  // gives the same result as the query; a stale `at` (another point) is
  // ignored.
  for (const Vec3& start : {Vec3(c + 0.15 * Vec3(1, 1, 0).normalized()), Vec3(c + Vec3(-0.15, 0, 0)),
                            Vec3(c + 0.2 * Vec3(1, 1, 0.1).normalized())}) {
    Vec3 plain = start;
    int plain_steps = 0;
    const bool plain_ok = MakeFeasible(tree, c, 0.15, 0, o, &plain, &plain_steps);
    const Vec3 at = OntoSphere(c, 0.15, start);
    for (const KnownContainment& kc : {KnownContainment{at, tree.AnyContains(at, -o.tol, 0)},
                                       KnownContainment{Vec3(at + Vec3(1e-9, 0, 0)), false}}) {
      Vec3 hinted = start;
      int hinted_steps = 0;
      EXPECT_EQ(MakeFeasible(tree, c, 0.15, 0, o, &hinted, &hinted_steps, nullptr, &kc), plain_ok);
      EXPECT_EQ(hinted, plain);
      EXPECT_EQ(hinted_steps, plain_steps);
      // free_at_end: when set, the containment query at the result says no.
      Vec3 flagged = start;
      bool free_at_end = false;
      const bool flagged_ok = MakeFeasible(tree, c, 0.15, 0, o, &flagged, nullptr, nullptr, &kc, &free_at_end);
      EXPECT_EQ(flagged, plain);
      EXPECT_EQ(flagged_ok, plain_ok);
      if (free_at_end) {
        EXPECT_FALSE(tree.AnyContains(flagged, -o.tol, 0));
      }
      if (!flagged_ok) {
        EXPECT_FALSE(free_at_end);
      }
    }
  }
  // A point moved and then found free by the query reports it.
  {
    Vec3 moved = c + 0.15 * Vec3(1, 1, 0).normalized();
    bool free_at_end = false;
    ASSERT_TRUE(MakeFeasible(tree, c, 0.15, 0, o, &moved, nullptr, nullptr, nullptr, &free_at_end));
    EXPECT_TRUE(free_at_end);
  }
  // Completely swallowed: sphere 0 inside a big sphere -> infeasible.
  MatrixX3d C2 = C;
  VectorXd R2 = R;
  R2[1] = 0.5;
  const SphereTree swallow(C2, R2, ids);
  Vec3 y = c + Vec3(0.0, 0.0, 0.15);
  EXPECT_FALSE(MakeFeasible(swallow, c, 0.15, 0, o, &y));
  EXPECT_NEAR((y - c).norm(), 0.15, 1e-12);
}

TEST(DrawBatch, WithoutReplacement) {
  Rng rng(3);
  const std::vector<int> b = DrawBatch(100000, 10000, rng);
  ASSERT_EQ(b.size(), 10000u);
  EXPECT_TRUE(std::is_sorted(b.begin(), b.end()));
  EXPECT_EQ(std::set<int>(b.begin(), b.end()).size(), 10000u);
  EXPECT_GE(b.front(), 0);
  EXPECT_LT(b.back(), 100000);
  EXPECT_EQ(DrawBatch(50, 10000, rng).size(), 50u);
  EXPECT_EQ(DrawBatch(50, 0, rng).size(), 50u);
}

}  // namespace
}  // namespace arcs
