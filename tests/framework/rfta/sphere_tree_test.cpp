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

// n balls with centres uniform in the unit cube; ball i's radius is
// radius(i, centre, rng), drawn after its centre, and its id id(i).
template <class Radius, class Id>
Balls RandomBalls(int n, std::uint64_t seed, Radius radius, Id id) {
  Rng rng(seed);
  Balls b;
  b.C.resize(n, 3);
  b.R.resize(n);
  for (int i = 0; i < n; ++i) {
    const Vec3 c(rng.Uniform(), rng.Uniform(), rng.Uniform());
    b.C.row(i) = c.transpose();
    b.R[i] = radius(i, c, rng);
    b.ids.push_back(id(i));
  }
  return b;
}

// Balls whose radius grows with the distance from a sphere of radius 0.3,
// like (shrunk) SDF data, plus a few small random ones: realistic radii, and
// gaps near the sphere where queries answer "none".
Balls MakeBalls(int n, std::uint64_t seed) {
  return RandomBalls(
      n, seed,
      [](int i, const Vec3& c, Rng& rng) {
        const double d = std::abs((c - Vec3(0.5, 0.5, 0.5)).norm() - 0.3);
        return i % 17 == 0 ? rng.Uniform(0.0, 0.05) : 0.9 * d;
      },
      [](int i) { return 1000 + i; });
}

double Dist(const Balls& b, int i, const Vec3& x) { return (Vec3(b.C.row(i).transpose()) - x).norm(); }

// Balls for the local-list tests, in three families: radii nearly affine in
// the centre (0.95 times the distance to the plane z = 0.45, jittered by a
// relative 1e-4: the nodes' affine bound is tight), SDF radii of a sphere
// (affine only locally), and random radii. Ids repeat: ball i has id 2000 + i % (n / 3), one of each family.
Balls MakeMixedBalls(int n, std::uint64_t seed) {
  return RandomBalls(
      n, seed,
      [](int i, const Vec3& c, Rng& rng) {
        if (i % 3 == 0) return 0.95 * std::abs(c.z() - 0.45) * (1.0 + 1e-4 * rng.Uniform(-1.0, 1.0));
        if (i % 3 == 1) return 0.9 * std::abs((c - Vec3(0.5, 0.5, 0.5)).norm() - 0.3);
        return rng.Uniform(0.0, 0.08);
      },
      [n](int i) { return 2000 + i % (n / 3); });
}

// A box and offset for CollectLocal.
struct LocalBox {
  Vec3 lo, hi;
  double offset;
};

// Appends 16 balls almost tangent to the box's offset shell: |p - c| - r =
// offset -+ delta at the box point p nearest to c, delta in [1e-9, 1e-6]
// (alternately inside the contract, which must list them, and just outside).
// The first 8 lie beyond the corners (p is the corner, a query point), the
// others anywhere within 0.1 of the box. Ids: first_id + m % id_mod (id_mod
// 0: first_id + m), m counting all balls.
void PlantNearTangent(const LocalBox& box, int first_id, int id_mod, Rng& rng, Balls* b) {
  for (int t = 0; t < 16; ++t) {
    Vec3 c;
    if (t < 8) {
      Vec3 v(std::abs(rng.Normal()), std::abs(rng.Normal()), std::abs(rng.Normal()));
      v = rng.Uniform(0.03, 0.1) * v.normalized();
      for (int a = 0; a < 3; ++a) c[a] = (t >> a) & 1 ? box.hi[a] + v[a] : box.lo[a] - v[a];
    } else {
      for (int a = 0; a < 3; ++a) c[a] = rng.Uniform(box.lo[a] - 0.1, box.hi[a] + 0.1);
    }
    const double gap = (c.cwiseMax(box.lo).cwiseMin(box.hi) - c).norm();
    const double delta = std::pow(10.0, rng.Uniform(-9.0, -6.0));
    const double r = gap - box.offset + (t % 2 ? delta : -delta);
    if (!(r > 0.0)) continue;
    const int m = static_cast<int>(b->R.size());
    b->C.conservativeResize(m + 1, 3);
    b->R.conservativeResize(m + 1);
    b->C.row(m) = c.transpose();
    b->R[m] = r;
    b->ids.push_back(first_id + (id_mod > 0 ? m % id_mod : m));
  }
}

// Points of the box [lo, hi]: the 8 corners, the centre, a point on each of
// the 6 faces, and `random` interior points.
std::vector<Vec3> BoxPoints(const Vec3& lo, const Vec3& hi, int random, Rng& rng) {
  std::vector<Vec3> p;
  for (int m = 0; m < 8; ++m)
    p.emplace_back(m & 1 ? hi[0] : lo[0], m & 2 ? hi[1] : lo[1], m & 4 ? hi[2] : lo[2]);
  p.push_back((0.5 * (lo + hi)).cwiseMax(lo).cwiseMin(hi));
  auto inside = [&] {
    Vec3 x;
    for (int a = 0; a < 3; ++a) x[a] = rng.Uniform(lo[a], hi[a]);
    return Vec3(x.cwiseMax(lo).cwiseMin(hi));
  };
  for (int a = 0; a < 3; ++a) {
    for (int s = 0; s < 2; ++s) {
      Vec3 x = inside();
      x[a] = s ? hi[a] : lo[a];
      p.push_back(x);
    }
  }
  for (int t = 0; t < random; ++t) p.push_back(inside());
  return p;
}

// Brute force over the tree's balls (tree order): the ids of the balls other
// than `ignore` with |x - c| - r < offset, deepest first (ties by id), at most k.
std::vector<int> BruteDeepest(const SphereTree& tree, const Vec3& x, double offset, int k, int ignore) {
  std::vector<std::pair<double, int>> keys;
  for (int j = 0; j < tree.Size(); ++j) {
    const SphereTree::Ball& b = tree.ball(j);
    const double key = (x - Vec3(b.x, b.y, b.z)).norm() - b.r;
    if (tree.id(j) != ignore && key < offset) keys.push_back({key, tree.id(j)});
  }
  std::sort(keys.begin(), keys.end());
  std::vector<int> ids;
  for (std::size_t t = 0; t < keys.size() && static_cast<int>(t) < k; ++t) ids.push_back(keys[t].second);
  return ids;
}

// Is there a ball other than `ignore` with |x - c| < r + offset? Over all
// balls, or (list) over the listed ones only.
bool BruteAny(const SphereTree& tree, const Vec3& x, double offset, int ignore,
              const std::vector<int>* list = nullptr) {
  const int n = list ? static_cast<int>(list->size()) : tree.Size();
  for (int t = 0; t < n; ++t) {
    const int j = list ? (*list)[t] : t;
    const SphereTree::Ball& b = tree.ball(j);
    if (tree.id(j) != ignore && (x - Vec3(b.x, b.y, b.z)).norm() < b.r + offset) return true;
  }
  return false;
}

std::vector<int> TreeIds(const SphereTree& tree, const std::vector<int>& indices) {
  std::vector<int> ids;
  for (int k : indices) ids.push_back(tree.id(k));
  return ids;
}

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

// CollectLocal's contract, and the point queries' local-list path, against
// brute force: random balls (SDF-like, nearly affine and random radii; unique
// and repeated ids), boxes of sizes 0 (a point) to 0.3, flat ones, near the
// surfaces and away from the balls, offsets from -1e-2 to 2e-2.
TEST(SphereTree, CollectLocalListsEveryBallNearTheBox) {
  const double kInf = std::numeric_limits<double>::infinity();
  const double offsets[] = {-1e-2, -1e-3, 0.0, 1e-3, 2e-2};
  const double sizes[] = {0.0, 1e-4, 3e-3, 0.02, 0.08, 0.3};
  int listed = 0, empty_sets = 0, found = 0, not_found = 0;
  for (int data = 0; data < 2; ++data) {
    Balls b = data == 0 ? MakeBalls(3000, 7) : MakeMixedBalls(3000, 13);
    Rng rng(100 + data), plant_rng(300 + data);
    // Boxes: centres anywhere (also outside the balls' cube, and far from
    // all balls), near the sphere |x - (0.5,0.5,0.5)| = 0.3, near the plane
    // z = 0.45; balls almost tangent to the latter two kinds are added.
    std::vector<LocalBox> boxes;
    for (const double offset : offsets) {
      for (int j = 0; j < 12; ++j) {
        Vec3 mid(rng.Uniform(-0.2, 1.2), rng.Uniform(-0.2, 1.2), rng.Uniform(-0.2, 1.2));
        if (j % 3 == 1)
          mid = Vec3(0.5, 0.5, 0.5) +
                rng.Uniform(0.29, 0.31) * Vec3(rng.Normal(), rng.Normal(), rng.Normal()).normalized();
        if (j % 3 == 2) mid.z() = 0.45 + rng.Uniform(-0.02, 0.02);
        if (j == 6 || j == 9) mid = Vec3::Constant(rng.Uniform(1.7, 2.0));  // no ball near
        Vec3 half = 0.5 * sizes[j % 6] * Vec3(rng.Uniform(0.5, 1.0), rng.Uniform(0.5, 1.0), rng.Uniform(0.5, 1.0));
        if (j % 4 == 3) half[rng.UniformInt(3)] = 0.0;  // flat box
        boxes.push_back({mid - half, mid + half, offset});
        if (j % 3 != 0)
          PlantNearTangent(boxes.back(), data == 0 ? 5000 : 2000, data == 0 ? 0 : 1000, plant_rng, &b);
      }
    }
    const SphereTree tree(b.C, b.R, b.ids);
    const int n = tree.Size();
    for (std::size_t j = 0; j < boxes.size(); ++j) {
      const Vec3 lo = boxes[j].lo, hi = boxes[j].hi;
      const double offset = boxes[j].offset;
      SCOPED_TRACE(::testing::Message() << "data " << data << " offset " << offset << " box " << j << " lo "
                                        << lo.transpose() << " hi " << hi.transpose());

      SphereTree::LocalSet set;
      tree.CollectLocal(lo, hi, offset, &set);
      EXPECT_TRUE(set.lo == lo && set.hi == hi);
      EXPECT_EQ(set.offset, offset);
      std::vector<char> in(n, 0);
      for (int k : set.balls) {
        ASSERT_GE(k, 0);
        ASSERT_LT(k, n);
        EXPECT_FALSE(in[k]) << "ball " << k << " listed twice";
        in[k] = 1;
      }
      listed += static_cast<int>(set.balls.size());
      empty_sets += set.balls.empty();

      // 1. Every ball within `offset` of some point of the box is listed:
      // at the box point nearest to each centre (the exact test) and at
      // the sampled points.
      int missing = 0;
      for (int k = 0; k < n; ++k) {
        const SphereTree::Ball& bk = tree.ball(k);
        const Vec3 c(bk.x, bk.y, bk.z);
        if ((c.cwiseMax(lo).cwiseMin(hi) - c).norm() - bk.r < offset && !in[k]) ++missing;
      }
      EXPECT_EQ(missing, 0) << "balls within offset of the box's nearest point not listed";
      std::vector<double> d(n);
      for (const Vec3& x : BoxPoints(lo, hi, 4, rng)) {
        missing = 0;
        for (int k = 0; k < n; ++k) {
          const SphereTree::Ball& bk = tree.ball(k);
          d[k] = (x - Vec3(bk.x, bk.y, bk.z)).norm();
          if (d[k] - bk.r < offset && !in[k]) ++missing;
        }
        EXPECT_EQ(missing, 0) << "balls within offset of x = " << x.transpose() << " not listed";

        // 2. The list serves x for offsets up to its own, nowhere outside the box.
        EXPECT_TRUE(set.Serves(x, offset));
        EXPECT_TRUE(set.Serves(x, offset - 1e-3));
        EXPECT_TRUE(set.Serves(x, -kInf));
        EXPECT_FALSE(set.Serves(x, std::nextafter(offset, kInf)));
        EXPECT_FALSE(set.Serves(x, offset + 1e-3));
        for (int a = 0; a < 3; ++a) {
          Vec3 y = x;
          y[a] = std::nextafter(lo[a], -kInf);
          EXPECT_FALSE(set.Serves(y, offset));
          y[a] = std::nextafter(hi[a], kInf);
          EXPECT_FALSE(set.Serves(y, offset));
        }

        // 3. Served queries answer as the tree and brute force do. Ignored
        // ids: none, a random one, the deepest ball's (ids repeat in data 1).
        int deepest = 0;
        for (int k = 1; k < n; ++k)
          if (d[k] - tree.ball(k).r < d[deepest] - tree.ball(deepest).r) deepest = k;
        const int ignores[] = {-1, tree.id(static_cast<int>(rng.UniformInt(n))), tree.id(deepest)};
        for (const double q : {offset, offset - 2e-3, std::min(offset, -1e-3)}) {
          for (const int ignore : ignores) {
            bool any = false;
            for (int k = 0; k < n && !any; ++k) any = tree.id(k) != ignore && d[k] < tree.ball(k).r + q;
            const int with = tree.FindContaining(x, q, ignore, &set);
            const int without = tree.FindContaining(x, q, ignore);
            EXPECT_EQ(with >= 0, any) << "q " << q << " ignore " << ignore;
            EXPECT_EQ(without >= 0, any) << "q " << q << " ignore " << ignore;
            EXPECT_EQ(tree.AnyContains(x, q, ignore, &set), any);
            if (with >= 0) {
              ASSERT_LT(with, n);
              EXPECT_TRUE(in[with]);
              EXPECT_NE(tree.id(with), ignore);
              EXPECT_TRUE(tree.Contains(with, x, q, ignore));
              EXPECT_LT(d[with], tree.ball(with).r + q);
            }
            found += any;
            not_found += !any;
            std::vector<int> deep_with, deep_without;
            for (const int kk : {1, 4, n}) {
              tree.DeepestContaining(x, q, kk, ignore, &deep_with, &set);
              tree.DeepestContaining(x, q, kk, ignore, &deep_without);
              EXPECT_EQ(deep_with, deep_without) << "q " << q << " k " << kk << " ignore " << ignore;
            }
            // (deep_with is the k = n answer: every ball with key < q.)
            EXPECT_EQ(TreeIds(tree, deep_with), BruteDeepest(tree, x, q, n, ignore));
          }
        }
      }
    }
  }
  // The boxes exercise short, long and empty lists, and both answers.
  EXPECT_GT(listed, 1000);
  EXPECT_GT(empty_sets, 0);
  EXPECT_GT(found, 1000);
  EXPECT_GT(not_found, 1000);
}

// Clusters of balls beyond one corner of a box, almost tangent to the
// corner's offset shell (|p - c| - r = offset -+ delta, delta in [1e-9, 1e-6])
// with radii affine along the diagonal ray, as SDF radii are along a
// gradient line. The node bounds at the box centre are then tight: a ball
// listed by the contract is only hd (the half diagonal) below them, which
// CollectLocal's pruning must allow for in full.
TEST(SphereTree, CollectLocalKeepsBallsTangentAtACorner) {
  Rng rng(17);
  int listed = 0;
  for (const double offset : {-1e-3, 0.0, 2e-3}) {
    for (const double size : {1e-3, 0.05, 0.4}) {
      for (int corner = 0; corner < 8; ++corner) {
        const Vec3 lo(rng.Uniform(), rng.Uniform(), rng.Uniform());
        const Vec3 hi = lo + size * Vec3(rng.Uniform(0.5, 1.0), rng.Uniform(0.5, 1.0), rng.Uniform(0.5, 1.0));
        const Vec3 p(corner & 1 ? hi[0] : lo[0], corner & 2 ? hi[1] : lo[1], corner & 4 ? hi[2] : lo[2]);
        const Vec3 dir = (p - 0.5 * (lo + hi)).normalized();
        Balls b;
        const int m = 40;
        b.C.resize(m, 3);
        b.R.resize(m);
        for (int t = 0; t < m; ++t) {
          const double s = rng.Uniform(0.05, 0.3);
          const Vec3 c = p + s * dir + 1e-4 * s * Vec3(rng.Normal(), rng.Normal(), rng.Normal());
          const double gap = (c.cwiseMax(lo).cwiseMin(hi) - c).norm();
          const double delta = std::pow(10.0, rng.Uniform(-9.0, -6.0));
          b.C.row(t) = c.transpose();
          b.R[t] = gap - offset + (t % 2 ? delta : -delta);
          b.ids.push_back(t % 10);
        }
        const SphereTree tree(b.C, b.R, b.ids);
        SCOPED_TRACE(::testing::Message() << "offset " << offset << " size " << size << " corner " << corner);
        SphereTree::LocalSet set;
        tree.CollectLocal(lo, hi, offset, &set);
        std::vector<char> in(m, 0);
        for (int k : set.balls) in[k] = 1;
        int missing = 0;
        for (int k = 0; k < m; ++k) {
          const SphereTree::Ball& bk = tree.ball(k);
          const Vec3 c(bk.x, bk.y, bk.z);
          if ((c.cwiseMax(lo).cwiseMin(hi) - c).norm() - bk.r < offset && !in[k]) ++missing;
          if ((p - c).norm() - bk.r < offset && !in[k]) ++missing;
        }
        EXPECT_EQ(missing, 0);
        listed += static_cast<int>(set.balls.size());
        // At the corner, the listed half of the balls contain p.
        ASSERT_TRUE(set.Serves(p, offset));
        for (const int ignore : {-1, 3}) {
          const int with = tree.FindContaining(p, offset, ignore, &set);
          EXPECT_GE(with, 0);
          EXPECT_EQ(with >= 0, tree.FindContaining(p, offset, ignore) >= 0);
          if (with >= 0) {
            EXPECT_TRUE(tree.Contains(with, p, offset, ignore));
          }
          std::vector<int> deep_with, deep_without;
          tree.DeepestContaining(p, offset, 5, ignore, &deep_with, &set);
          tree.DeepestContaining(p, offset, 5, ignore, &deep_without);
          EXPECT_EQ(deep_with, deep_without);
          EXPECT_EQ(TreeIds(tree, deep_with), BruteDeepest(tree, p, offset, 5, ignore));
        }
      }
    }
  }
  EXPECT_GE(listed, 3 * 3 * 8 * 20);  // at least the balls within offset of the corner
}

// 4. A list that does not serve the query (x outside its box, or a larger
// offset) is not used: the tree answers, correctly, also where the list
// alone would not.
TEST(SphereTree, LocalListNotServingFallsBackToTree) {
  const double kInf = std::numeric_limits<double>::infinity();
  int list_would_differ = 0;
  for (int data = 0; data < 2; ++data) {
    const Balls b = data == 0 ? MakeBalls(3000, 7) : MakeMixedBalls(3000, 13);
    const SphereTree tree(b.C, b.R, b.ids);
    const int n = tree.Size();
    Rng rng(200 + data);
    for (int j = 0; j < 40; ++j) {
      const double offset = j % 2 ? -1e-3 : 1e-3;
      const Vec3 mid = Vec3(0.5, 0.5, 0.5) +
                       rng.Uniform(0.0, 0.45) * Vec3(rng.Normal(), rng.Normal(), rng.Normal()).normalized();
      const Vec3 half = Vec3::Constant(rng.Uniform(1e-3, 0.02));
      const Vec3 lo = mid - half, hi = mid + half;
      SphereTree::LocalSet set;
      tree.CollectLocal(lo, hi, offset, &set);
      SCOPED_TRACE(::testing::Message() << "data " << data << " box " << j << " lo " << lo.transpose());
      std::vector<std::pair<Vec3, double>> queries;  // (x, q) the list does not serve
      for (const Vec3& x : BoxPoints(lo, hi, 2, rng)) {
        queries.push_back({x, offset + 0.01});  // inside, offset above the list's
        queries.push_back({x, std::nextafter(offset, kInf)});
        Vec3 y = x;
        const int a = static_cast<int>(rng.UniformInt(3));
        y[a] = rng.Uniform() < 0.5 ? std::nextafter(lo[a], -kInf) : std::nextafter(hi[a], kInf);
        queries.push_back({y, offset});  // just outside
        queries.push_back({Vec3(1.0, 1.0, 1.0) - x, offset});  // mirrored, usually far
        queries.push_back({x + Vec3(0.05, -0.03, 0.02), offset - 1e-3});
      }
      for (const auto& [x, q] : queries) {
        if (set.Serves(x, q)) continue;  // the mirrored point can land in the box
        const int ignore = tree.id(static_cast<int>(rng.UniformInt(n)));
        const bool any = BruteAny(tree, x, q, ignore);
        const int with = tree.FindContaining(x, q, ignore, &set);
        EXPECT_EQ(with >= 0, any) << "x " << x.transpose() << " q " << q;
        EXPECT_EQ(tree.AnyContains(x, q, ignore, &set), any);
        if (with >= 0) {
          EXPECT_TRUE(tree.Contains(with, x, q, ignore));
        }
        std::vector<int> deep;
        tree.DeepestContaining(x, q, 6, ignore, &deep, &set);
        const std::vector<int> expect = BruteDeepest(tree, x, q, 6, ignore);
        EXPECT_EQ(TreeIds(tree, deep), expect) << "x " << x.transpose() << " q " << q;
        if (BruteAny(tree, x, q, ignore, &set.balls) != any) ++list_would_differ;
      }
    }
  }
  EXPECT_GT(list_would_differ, 20);  // the fallback is exercised where it matters
  // An empty tree's list is empty and serves its box.
  const SphereTree empty;
  SphereTree::LocalSet set;
  set.balls = {7};
  empty.CollectLocal(Vec3::Zero(), Vec3::Ones(), 0.5, &set);
  EXPECT_TRUE(set.balls.empty());
  EXPECT_TRUE(set.Serves(Vec3::Constant(0.5), 0.5));
  EXPECT_EQ(empty.FindContaining(Vec3::Constant(0.5), 0.5, -1, &set), -1);
  std::vector<int> deep = {1};
  empty.DeepestContaining(Vec3::Constant(0.5), 0.5, 3, -1, &deep, &set);
  EXPECT_TRUE(deep.empty());
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
