#include "framework/rfta/sphere_tree.h"

#include "framework/util/rng.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace arcs {
namespace {

struct Balls {
  MatrixX3d C;
  VectorXd R;
  std::vector<int> ids;
};

// Balls whose radius grows with the distance from a sphere of radius 0.3,
// like (shrunk) SDF data, plus a few small random ones: realistic radii, and
// gaps near the sphere where queries answer "none".
Balls MakeBalls(int n, std::uint64_t seed) {
  Rng rng(seed);
  Balls b;
  b.C.resize(n, 3);
  b.R.resize(n);
  for (int i = 0; i < n; ++i) {
    const Vec3 c(rng.Uniform(), rng.Uniform(), rng.Uniform());
    b.C.row(i) = c.transpose();
    const double d = std::abs((c - Vec3(0.5, 0.5, 0.5)).norm() - 0.3);
    b.R[i] = i % 17 == 0 ? rng.Uniform(0.0, 0.05) : 0.9 * d;
    b.ids.push_back(1000 + i);
  }
  return b;
}

double Dist(const Balls& b, int i, const Vec3& x) { return (Vec3(b.C.row(i).transpose()) - x).norm(); }

TEST(SphereTree, PointQueriesMatchBruteForce) {
  const Balls b = MakeBalls(3000, 7);
  const SphereTree tree(b.C, b.R, b.ids);
  ASSERT_EQ(tree.Size(), 3000);
  Rng rng(11);
  const double tol = 1e-3;
  int contained = 0;
  for (int q = 0; q < 400; ++q) {
    // Half the queries near the sphere |x - (0.5,0.5,0.5)| = 0.3.
    Vec3 x(rng.Uniform(-0.1, 1.1), rng.Uniform(-0.1, 1.1), rng.Uniform(-0.1, 1.1));
    if (q % 2) x = Vec3(0.5, 0.5, 0.5) + rng.Uniform(0.28, 0.32) * Vec3(rng.Normal(), rng.Normal(), rng.Normal()).normalized();
    const int ignore = 1000 + static_cast<int>(rng.UniformInt(3000));
    // AnyContains.
    bool any = false;
    for (int i = 0; i < 3000; ++i)
      any = any || (b.ids[i] != ignore && Dist(b, i, x) < b.R[i] - tol);
    EXPECT_EQ(tree.AnyContains(x, -tol, ignore), any);
    // CollectContaining: every containing ball's id, each once; a subset of
    // the balls (every third id) contains x exactly when the list holds one.
    std::vector<int> inside, expect;
    for (int i = 0; i < 3000; ++i)
      if (b.ids[i] != ignore && Dist(b, i, x) < b.R[i] - tol) expect.push_back(b.ids[i]);
    tree.CollectContaining(x, -tol, ignore, &inside);
    std::sort(inside.begin(), inside.end());
    EXPECT_EQ(inside, expect);
    std::vector<int> third;
    for (int i = 0; i < 3000; i += 3) third.push_back(i);
    const SphereTree subset(b.C, b.R, b.ids, &third);
    bool in_subset = false;
    for (int id : inside) in_subset = in_subset || (id - 1000) % 3 == 0;
    EXPECT_EQ(subset.AnyContains(x, -tol, ignore), in_subset);
    // FindContaining names a ball that contains x (by the same test), or -1.
    const int k = tree.FindContaining(x, -tol, ignore);
    EXPECT_EQ(k >= 0, any);
    if (k >= 0) {
      EXPECT_TRUE(tree.Contains(k, x, -tol, ignore));
      EXPECT_NE(tree.id(k), ignore);
      const SphereTree::Ball& bk = tree.ball(k);
      EXPECT_LT((x - Vec3(bk.x, bk.y, bk.z)).norm(), bk.r - tol + 1e-12);
    }
    contained += any;
    // DeepestContaining: the k smallest |x - c| - r below +tol, ties by id.
    std::vector<std::pair<double, int>> keys;
    for (int i = 0; i < 3000; ++i) {
      const double key = Dist(b, i, x) - b.R[i];
      if (b.ids[i] != ignore && key < tol) keys.push_back({key, b.ids[i]});
    }
    std::sort(keys.begin(), keys.end());
    std::vector<int> found;
    tree.DeepestContaining(x, tol, 5, ignore, &found);
    ASSERT_EQ(found.size(), std::min<std::size_t>(5, keys.size()));
    for (std::size_t t = 0; t < found.size(); ++t) EXPECT_EQ(tree.id(found[t]), keys[t].second);
    // AnyCovers and DistanceToUnion with the rasteriser's shrink.
    bool cov = false;
    double dmin = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 3000; ++i) {
      cov = cov || (Vec3(b.C.row(i).transpose()) - x).squaredNorm() <= 0.95 * b.R[i] * b.R[i];
      dmin = std::min(dmin, Dist(b, i, x) - std::sqrt(0.95) * b.R[i]);
    }
    EXPECT_EQ(tree.AnyCovers(x, 0.95), cov);
    EXPECT_NEAR(tree.DistanceToUnion(x, std::sqrt(0.95)), dmin, 1e-12);
  }
  EXPECT_GT(contained, 20);  // the queries exercise both answers
  EXPECT_LT(contained, 380);
}

TEST(SphereTree, BoxQueriesMatchBruteForce) {
  const Balls b = MakeBalls(2000, 3);
  const SphereTree tree(b.C, b.R, b.ids);
  Rng rng(5);
  int covered = 0, none = 0;
  for (int q = 0; q < 300; ++q) {
    Vec3 lo(rng.Uniform(), rng.Uniform(), rng.Uniform());
    if (q % 2) lo = Vec3(0.5, 0.5, 0.5) + 0.3 * Vec3(rng.Normal(), rng.Normal(), rng.Normal()).normalized();
    const Vec3 hi = lo + Vec3::Constant(rng.Uniform(0.001, 0.1) / (q % 2 ? 20 : 1));
    std::vector<int> expect;
    bool cover = false;
    for (int i = 0; i < 2000; ++i) {
      const Vec3 c = b.C.row(i).transpose();
      const Vec3 nearest = c.cwiseMax(lo).cwiseMin(hi);
      Vec3 far;
      for (int a = 0; a < 3; ++a) far[a] = std::abs(c[a] - lo[a]) > std::abs(c[a] - hi[a]) ? lo[a] : hi[a];
      const double rr = 0.95 * b.R[i] * b.R[i];
      if ((nearest - c).squaredNorm() <= rr) expect.push_back(b.ids[i]);
      cover = cover || (far - c).squaredNorm() <= rr;
    }
    std::vector<int> got;
    tree.CollectIntersectingBox(lo, hi, 0.95, &got);
    for (int& k : got) k = tree.id(k);
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, expect);
    EXPECT_EQ(tree.AnyIntersectsBox(lo, hi, 0.95), !expect.empty());
    EXPECT_EQ(tree.AnyCoversBox(lo, hi, 0.95), cover);
    covered += cover;
    none += expect.empty();
  }
  EXPECT_GT(covered, 5);
  EXPECT_GT(none, 0);
}

TEST(SphereTree, SubsetAndEmpty) {
  const Balls b = MakeBalls(100, 9);
  const std::vector<int> members = {3, 10, 42};
  const SphereTree tree(b.C, b.R, b.ids, &members);
  ASSERT_EQ(tree.Size(), 3);
  std::vector<int> ids = {tree.id(0), tree.id(1), tree.id(2)};
  std::sort(ids.begin(), ids.end());
  EXPECT_EQ(ids, (std::vector<int>{1003, 1010, 1042}));
  const SphereTree empty;
  EXPECT_FALSE(empty.AnyContains(Vec3::Zero(), 0.0, -1));
  EXPECT_EQ(empty.DistanceToUnion(Vec3::Zero(), 1.0), std::numeric_limits<double>::infinity());
}

}  // namespace
}  // namespace arcs
