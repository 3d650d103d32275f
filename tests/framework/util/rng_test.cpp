#include "framework/util/parallel.h"
#include "framework/util/rng.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace arcs {
namespace {

TEST(RngTest, SameSeedSameSequenceDifferentSeedDifferent) {
  Rng a(42), b(42), c(43);
  for (int i = 0; i < 100; ++i) {
    const auto x = a.NextU64();
    EXPECT_EQ(x, b.NextU64());
    EXPECT_NE(x, c.NextU64());
  }
}

TEST(RngTest, UniformAndNormalMoments) {
  Rng r(7);
  const int n = 200000;
  double su = 0, sn = 0, sn2 = 0;
  for (int i = 0; i < n; ++i) {
    const double u = r.Uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    su += u;
    const double z = r.Normal();
    sn += z;
    sn2 += z * z;
  }
  EXPECT_NEAR(su / n, 0.5, 0.005);
  EXPECT_NEAR(sn / n, 0.0, 0.01);
  EXPECT_NEAR(sn2 / n, 1.0, 0.02);
}

TEST(ParallelTest, CoversRangeOnceIndependentOfThreads) {
  for (int threads : {1, 2}) {
    ThreadLimit limit(threads);
    std::vector<int> hits(100000, 0);
    ParallelFor(static_cast<std::int64_t>(hits.size()), [&](std::int64_t b, std::int64_t e) {
      for (auto i = b; i < e; ++i) hits[i] += 1;
    }, 100);
    for (int h : hits) ASSERT_EQ(h, 1);
  }
}

}  // namespace
}  // namespace arcs
