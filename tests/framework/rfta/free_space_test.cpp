#include "framework/rfta/free_space.h"

#include "framework/error.h"
#include "framework/util/parallel.h"
#include "tests/framework/rfta/rfta_test_shapes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace arcs {
namespace {

using rfta_test::BallSdfGrid;

// The official dense rule, brute force: every cell of the restricted grid,
// occupancy of its point by any ball, band = free cells with an occupied
// 3^d neighbour. Returns the band points sorted lexicographically.
std::vector<std::array<double, 3>> DenseBand(const SphereSet& s, int res, double shrink, bool jitter,
                                             std::uint64_t seed) {
  const int dim = s.dim;
  std::int64_t lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
  for (int a = 0; a < dim; ++a) {
    const double bmin = (s.centers.col(a) - s.radii).minCoeff();
    const double bmax = (s.centers.col(a) + s.radii).maxCoeff();
    lo[a] = static_cast<std::int64_t>(std::clamp(std::floor(bmin * res) - 1.0, 0.0, double(res)));
    hi[a] = static_cast<std::int64_t>(std::clamp(std::floor(bmax * res) + 2.0, 0.0, double(res)));
  }
  const std::int64_t nx = hi[0] - lo[0], ny = hi[1] - lo[1], nz = hi[2] - lo[2];
  std::vector<char> occ(nx * ny * nz, 0);
  for (std::int64_t k = 0; k < nz; ++k)
    for (std::int64_t j = 0; j < ny; ++j)
      for (std::int64_t i = 0; i < nx; ++i) {
        const Vec3 p = RasterCellPoint(seed, res, dim, jitter, lo[0] + i, lo[1] + j, lo[2] + k);
        for (int t = 0; t < s.Size(); ++t)
          if ((p - Vec3(s.centers.row(t).transpose())).squaredNorm() <= shrink * s.radii[t] * s.radii[t]) {
            occ[i + nx * (j + ny * k)] = 1;
            break;
          }
      }
  std::vector<std::array<double, 3>> out;
  const int zr = dim == 3 ? 1 : 0;
  for (std::int64_t k = 0; k < nz; ++k)
    for (std::int64_t j = 0; j < ny; ++j)
      for (std::int64_t i = 0; i < nx; ++i) {
        if (occ[i + nx * (j + ny * k)]) continue;
        bool near = false;
        for (int dz = -zr; dz <= zr; ++dz)
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
              const std::int64_t x = i + dx, y = j + dy, z = k + dz;
              if (x < 0 || y < 0 || z < 0 || x >= nx || y >= ny || z >= nz) continue;
              near = near || occ[x + nx * (y + ny * z)];
            }
        if (!near) continue;
        const Vec3 p = RasterCellPoint(seed, res, dim, jitter, lo[0] + i, lo[1] + j, lo[2] + k);
        out.push_back({p.x(), p.y(), p.z()});
      }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::array<double, 3>> Sorted(const MatrixX3d& P) {
  std::vector<std::array<double, 3>> v(P.rows());
  for (int i = 0; i < P.rows(); ++i) v[i] = {P(i, 0), P(i, 1), P(i, 2)};
  std::sort(v.begin(), v.end());
  return v;
}

// Distance from x to the union of the balls (c, sqrt(shrink) r) (negative inside).
double UnionDistance(const SphereSet& s, const Vec3& x, double shrink) {
  double d = std::numeric_limits<double>::infinity();
  for (int t = 0; t < s.Size(); ++t)
    d = std::min(d, (x - Vec3(s.centers.row(t).transpose())).norm() - std::sqrt(shrink) * s.radii[t]);
  return d;
}

TEST(Rasterize, EqualsDenseOfficialRule3D) {
  const SignedSpheres sp = SplitSpheresBySign(BallSdfGrid(10, 0.3), {});
  for (bool jitter : {true, false}) {
    for (int sign : {1, -1}) {
      const SphereSet& s = sp.Get(sign);
      RasterizeOptions o;
      o.jitter = jitter;
      RasterizeStats st;
      const MatrixX3d band = RasterizeNarrowBand(s, 60, o, 1234, &st);
      const auto dense = DenseBand(s, 60, 0.95, jitter, 1234);
      EXPECT_GT(dense.size(), 500u);
      EXPECT_EQ(Sorted(band), dense) << "sign " << sign << " jitter " << jitter;
      EXPECT_EQ(st.band_points, band.rows());
      EXPECT_GT(st.mixed_bricks, 0);
    }
  }
}

TEST(Rasterize, EqualsDenseOfficialRule2D) {
  const SignedSpheres sp = SplitSpheresBySign(BallSdfGrid(16, 0.27, 2), {});
  for (int sign : {1, -1}) {
    const SphereSet& s = sp.Get(sign);
    const MatrixX3d band = RasterizeNarrowBand(s, 203, RasterizeOptions(), 99);
    const auto dense = DenseBand(s, 203, 0.95, true, 99);
    EXPECT_GT(dense.size(), 100u);
    EXPECT_EQ(Sorted(band), dense) << "sign " << sign;
    for (int i = 0; i < band.rows(); ++i) EXPECT_EQ(band(i, 2), 0.0);
  }
}

TEST(Rasterize, BandIsFreeAndNearTheBoundary) {
  const SdfSamples samples = BallSdfGrid(20, 0.3);
  Context ctx(3);
  RasterizeStats st[2];
  const FreeSpaceSamples f = RasterizeFreeSpace(samples, RasterizeOptions(), ctx, st);
  ASSERT_EQ(static_cast<std::int64_t>(f.sign.size()), f.Size());
  EXPECT_EQ(st[0].resolution, 128);  // 21^3 samples: 64 * ceil(21 / 16)
  const SignedSpheres sp = SplitSpheresBySign(samples, {});
  const double cell = 1.0 / 128;
  std::int64_t counts[2] = {0, 0};
  for (std::int64_t j = 0; j < f.Size(); ++j) {
    const int sign = f.sign[j];
    const SphereSet& s = sp.Get(sign);
    const Vec3 u = sp.frame.ToUnit(f.points.row(j).transpose());
    const double d = UnionDistance(s, u, 0.95);
    EXPECT_GT(d, 0.0);                      // outside every ball of its sign
    EXPECT_LT(d, 2 * std::sqrt(3.0) * cell);  // within two cells of the union
    ++counts[sign > 0 ? 0 : 1];
  }
  EXPECT_EQ(counts[0], st[0].band_points);
  EXPECT_EQ(counts[1], st[1].band_points);
  EXPECT_GT(counts[0], 1000);
  EXPECT_GT(counts[1], 1000);
  // The positive spheres' free space is the ball's inside, the negative
  // spheres' its outside, plus thin pockets the shrunk spheres leave on the
  // other side (deeper inside the ball, where the inner spheres are small).
  // Grid spacing h = 0.05.
  for (std::int64_t j = 0; j < f.Size(); ++j) {
    const double r = f.points.row(j).norm();
    if (f.sign[j] > 0) {
      EXPECT_LT(r, 0.3 + 0.2 * 0.05);
    } else {
      EXPECT_GT(r, 0.3 - 0.4 * 0.05);
    }
    EXPECT_NEAR(r, 0.3, 0.4 * 0.05);
  }
}

TEST(Rasterize, DeterministicAcrossThreads) {
  const SdfSamples samples = BallSdfGrid(16, 0.31);
  Context ctx(8);
  FreeSpaceSamples a, b;
  {
    ThreadLimit one(1);
    a = RasterizeFreeSpace(samples, RasterizeOptions(), ctx);
  }
  {
    ThreadLimit two(2);
    b = RasterizeFreeSpace(samples, RasterizeOptions(), ctx);
  }
  EXPECT_EQ(a.points, b.points);
  EXPECT_EQ(a.sign, b.sign);
  Context other(9);
  const FreeSpaceSamples c = RasterizeFreeSpace(samples, RasterizeOptions(), other);
  EXPECT_FALSE(c.points.rows() == a.points.rows() && c.points == a.points);  // the seed matters
}

TEST(Rasterize, BadInputsThrow) {
  Context ctx;
  SdfSamples s = BallSdfGrid(4, 0.3);
  SdfSamples pos = s;
  pos.values = pos.values.cwiseAbs().array() + 0.01;
  EXPECT_THROW(RasterizeFreeSpace(pos, RasterizeOptions(), ctx), Error);
  SdfSamples neg = s;
  neg.values = -(neg.values.cwiseAbs().array() + 0.01);
  EXPECT_THROW(RasterizeFreeSpace(neg, RasterizeOptions(), ctx), Error);
  SdfSamples one;
  one.dim = 3;
  one.points = MatrixXd::Zero(1, 3);
  one.values = VectorXd::Constant(1, -0.1);
  EXPECT_THROW(RasterizeFreeSpace(one, RasterizeOptions(), ctx), Error);
  SdfSamples nan = s;
  nan.values[7] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(RasterizeFreeSpace(nan, RasterizeOptions(), ctx), Error);
  SdfSamples nanp = s;
  nanp.points(3, 1) = std::numeric_limits<double>::infinity();
  EXPECT_THROW(RasterizeFreeSpace(nanp, RasterizeOptions(), ctx), Error);
  RasterizeOptions bad;
  bad.shrink = 1.5;
  EXPECT_THROW(RasterizeFreeSpace(s, bad, ctx), OptionError);
  bad = RasterizeOptions();
  bad.resolution = 1;
  EXPECT_THROW(bad.Check(), OptionError);
}

TEST(Rasterize, ResolutionHeuristicMatchesOfficial) {
  EXPECT_EQ(RasterResolutionHeuristic(21 * 21 * 21, 3), 128);
  EXPECT_EQ(RasterResolutionHeuristic(41 * 41 * 41, 3), 192);
  EXPECT_EQ(RasterResolutionHeuristic(101 * 101 * 101, 3), 448);
  EXPECT_EQ(RasterResolutionHeuristic(7 * 7 * 7, 3), 64);
  EXPECT_EQ(RasterResolutionHeuristic(1000000000000LL, 3), 1024);  // cap
  EXPECT_EQ(LocalSearchHeuristic(21 * 21 * 21, 3), 42);
  EXPECT_EQ(LocalSearchHeuristic(41 * 41 * 41, 3), 82);
}

TEST(Rejection, PointsAreFreeAndCounted) {
  const SdfSamples samples = BallSdfGrid(10, 0.3);
  const SignedSpheres sp = SplitSpheresBySign(samples, {});
  RejectionOptions o;
  o.count = 3000;
  std::int64_t draws = 0;
  const MatrixX3d P = RejectionSampleFreeSpace(sp.positive, o, 5, &draws);
  ASSERT_EQ(P.rows(), 3000);
  EXPECT_GT(draws, 3000);
  for (int i = 0; i < P.rows(); ++i) {
    EXPECT_GT(UnionDistance(sp.positive, P.row(i).transpose(), 0.95), 0.0);
    EXPECT_TRUE((P.row(i).array() >= 0.0).all() && (P.row(i).array() <= 1.0).all());
  }
  // max_draws stops early with fewer points.
  o.max_draws = 3000;
  EXPECT_LT(RejectionSampleFreeSpace(sp.positive, o, 5).rows(), 3000);
  // Thread-independent.
  o.max_draws = 1000000;
  MatrixX3d a, b;
  {
    ThreadLimit one(1);
    a = RejectionSampleFreeSpace(sp.negative, o, 6);
  }
  {
    ThreadLimit two(2);
    b = RejectionSampleFreeSpace(sp.negative, o, 6);
  }
  EXPECT_EQ(a, b);
}

TEST(Metropolis, ConcentratesNearTheBoundary) {
  const SdfSamples samples = BallSdfGrid(10, 0.3);
  const SignedSpheres sp = SplitSpheresBySign(samples, {});
  MetropolisOptions o;
  o.count = 4000;
  o.chains = 16;
  RejectionOptions ro;
  ro.count = 4000;
  for (int sign : {1, -1}) {
    const SphereSet& s = sp.Get(sign);
    MatrixX3d a, b;
    {
      ThreadLimit one(1);
      a = MetropolisSampleFreeSpace(s, sp.num_samples, o, 17);
    }
    {
      ThreadLimit two(2);
      b = MetropolisSampleFreeSpace(s, sp.num_samples, o, 17);
    }
    EXPECT_EQ(a, b);
    ASSERT_EQ(a.rows(), 4000);
    const MatrixX3d u = RejectionSampleFreeSpace(s, ro, 17);
    double mh = 0.0, uni = 0.0;
    for (int i = 0; i < a.rows(); ++i) {
      const double d = UnionDistance(s, a.row(i).transpose(), 0.95);
      EXPECT_GT(d, 0.0);
      mh += d / a.rows();
    }
    for (int i = 0; i < u.rows(); ++i) uni += UnionDistance(s, u.row(i).transpose(), 0.95) / u.rows();
    EXPECT_LT(mh, 0.5 * uni) << "sign " << sign;  // closer to the spheres than uniform samples
  }
}

}  // namespace
}  // namespace arcs
