#include "framework/spatial/knn.h"

#include "framework/util/parallel.h"
#include "framework/util/rng.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <utility>
#include <vector>

namespace arcs {
namespace {

MatrixX3d RandomPoints(int n, std::uint64_t seed, double scale = 1.0) {
  Rng rng(seed);
  MatrixX3d P(n, 3);
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) P(i, k) = scale * rng.Uniform(-1.0, 1.0);
  return P;
}

// Brute-force (sq_dist, index) pairs sorted by distance then index.
std::vector<std::pair<double, int>> BruteSorted(const MatrixX3d& P, const Vec3& q) {
  std::vector<std::pair<double, int>> d(P.rows());
  for (int i = 0; i < P.rows(); ++i) d[i] = {(Vec3(P.row(i)) - q).squaredNorm(), i};
  std::sort(d.begin(), d.end());
  return d;
}

TEST(KdTree3, NearestMatchesBruteForce) {
  const MatrixX3d P = RandomPoints(3000, 1);
  const MatrixX3d Q = RandomPoints(1000, 2, 1.3);
  const KdTree3 tree(P);
  EXPECT_EQ(tree.Size(), 3000);
  Eigen::VectorXi idx;
  VectorXd d2;
  tree.NearestBatch(Q, &idx, &d2);
  for (int i = 0; i < Q.rows(); ++i) {
    const auto ref = BruteSorted(P, Q.row(i));
    ASSERT_EQ(idx[i], ref[0].second) << i;
    ASSERT_EQ(d2[i], ref[0].first);
    double s;
    EXPECT_EQ(tree.Nearest(Q.row(i), &s), ref[0].second);
    EXPECT_EQ(s, ref[0].first);
  }
}

TEST(KdTree3, TiesGoToLowestIndex) {
  // Duplicated points (a common case for samples on meshes) and a query
  // equidistant from two points.
  MatrixX3d P(6, 3);
  P << 1, 0, 0,  //
      0, 0, 0,   //
      5, 5, 5,   //
      0, 0, 0,   //
      -1, 0, 0,  //
      0, 0, 0;
  const KdTree3 tree(P);
  EXPECT_EQ(tree.Nearest(Vec3(0, 0, 0)), 1);
  EXPECT_EQ(tree.Nearest(Vec3(0, 0.1, 0)), 1);
  MatrixX3d Q(3, 3);
  Q << 0, 0, 0, 0, 0.2, 0, 4.9, 5, 5;
  Eigen::VectorXi idx;
  tree.NearestBatch(Q, &idx, nullptr);
  EXPECT_EQ(idx[0], 1);
  EXPECT_EQ(idx[1], 1);
  EXPECT_EQ(idx[2], 2);
  MatrixX3d P2(2, 3);
  P2 << 1, 0, 0, -1, 0, 0;
  EXPECT_EQ(KdTree3(P2).Nearest(Vec3(0, 0, 0)), 0);
}

TEST(KdTree3, KnnMatchesBruteForce) {
  const MatrixX3d P = RandomPoints(2000, 3);
  const MatrixX3d Q = RandomPoints(200, 4);
  const KdTree3 tree(P);
  Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> out;
  tree.KnnBatch(Q, 7, &out);
  ASSERT_EQ(out.rows(), 200);
  ASSERT_EQ(out.cols(), 7);
  for (int i = 0; i < Q.rows(); ++i) {
    const auto ref = BruteSorted(P, Q.row(i));
    std::vector<double> d2;
    const std::vector<int> nn = tree.Knn(Q.row(i), 7, &d2);
    ASSERT_EQ(nn.size(), 7u);
    for (int k = 0; k < 7; ++k) {
      EXPECT_EQ(nn[k], ref[k].second);
      EXPECT_EQ(d2[k], ref[k].first);
      EXPECT_EQ(out(i, k), ref[k].second);
    }
  }
  // Fewer points than k: all of them, padded with -1 in the batch.
  MatrixX3d small(3, 3);
  small << 0, 0, 0, 1, 0, 0, 0, 2, 0;
  const KdTree3 st(small);
  EXPECT_EQ(st.Knn(Vec3(0.9, 0, 0), 5), (std::vector<int>{1, 0, 2}));
  st.KnnBatch(Q.topRows(2), 5, &out);
  EXPECT_EQ(out(0, 3), -1);
  EXPECT_EQ(out(1, 4), -1);
}

TEST(KdTree3, DeterministicAcrossThreadsAndClustered) {
  // Clustered data (many points at a few locations) plus uniform noise.
  Rng rng(5);
  MatrixX3d P(20000, 3);
  for (int i = 0; i < P.rows(); ++i)
    for (int k = 0; k < 3; ++k) P(i, k) = (i % 3 == 0) ? rng.Uniform(-1, 1) : 0.01 * (i % 7) + 1e-9 * rng.Normal();
  const MatrixX3d Q = RandomPoints(20000, 6);
  const KdTree3 tree(P);
  Eigen::VectorXi a, b;
  VectorXd da, db;
  {
    ThreadLimit one(1);
    tree.NearestBatch(Q, &a, &da);
  }
  {
    ThreadLimit two(2);
    tree.NearestBatch(Q, &b, &db);
  }
  EXPECT_EQ(a, b);
  EXPECT_EQ(da, db);
  for (int i = 0; i < 200; ++i) EXPECT_EQ(a[i], BruteSorted(P, Q.row(i))[0].second);
}

TEST(MortonOrder, PermutationWithZOrderBlocks) {
  // 4x4x4 grid, x fastest: the Z-curve visits the 2x2x2 corner block first.
  MatrixX3d P(64, 3);
  for (int k = 0, r = 0; k < 4; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) P.row(r++) << i, j, k;
  const std::vector<int> order = MortonOrder(P);
  std::vector<int> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (int i = 0; i < 64; ++i) ASSERT_EQ(sorted[i], i);
  EXPECT_EQ(order[0], 0);
  EXPECT_EQ(order[1], 1);   // (1,0,0)
  EXPECT_EQ(order[2], 4);   // (0,1,0)
  EXPECT_EQ(order[7], 21);  // (1,1,1)
  for (int s = 0; s < 8; ++s) EXPECT_LE(P.row(order[s]).maxCoeff(), 1.0);
  // Duplicates keep index order; empty input.
  MatrixX3d D = MatrixX3d::Zero(5, 3);
  EXPECT_EQ(MortonOrder(D), (std::vector<int>{0, 1, 2, 3, 4}));
  EXPECT_TRUE(MortonOrder(MatrixX3d(0, 3)).empty());
}

TEST(KdTree3, EmptyTree) {
  const KdTree3 tree(MatrixX3d(0, 3));
  EXPECT_EQ(tree.Size(), 0);
  double d2 = 0;
  EXPECT_EQ(tree.Nearest(Vec3::Zero(), &d2), -1);
  EXPECT_TRUE(std::isinf(d2));
  EXPECT_TRUE(tree.Knn(Vec3::Zero(), 3).empty());
  Eigen::VectorXi idx;
  tree.NearestBatch(RandomPoints(4, 7), &idx, nullptr);
  EXPECT_EQ(idx[3], -1);
}

}  // namespace
}  // namespace arcs
