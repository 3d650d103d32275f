// The official RFTA's screened Poisson settings (rfta_official_facts.md §2):
// PoissonRecon's area-normalised screening weight, the Open3D back-end
// (PoissonRecon 12: FEM degree 1, Neumann) and the estimated sample area.
#include "framework/reconstruct/poisson.h"
#include "framework/reconstruct/poisson_open3d.h"

#include "framework/spatial/topology.h"
#include "framework/util/rng.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

namespace arcs {
namespace {

constexpr double kPi = std::numbers::pi;

PointCloud SpherePoints(int n, double r = 0.5, std::uint64_t seed = 7) {
  PointCloud pc;
  pc.P.resize(n, 3);
  pc.N.resize(n, 3);
  Rng rng(seed);
  for (int i = 0; i < n; ++i) {
    const Vec3 d = Vec3(rng.Normal(), rng.Normal(), rng.Normal()).normalized();
    pc.N.row(i) = d;
    pc.P.row(i) = r * d;
  }
  return pc;
}

// The official geometry: depth 10 in a cube 3.2x the cloud, 1.5 samples per
// node, weight 10 in PoissonRecon's units, never re-solved.
PoissonOptions Official() {
  PoissonOptions o;
  o.depth = 10;
  o.scale = 3.2;
  o.samples_per_node = 1.5;
  o.point_weight = 10;
  o.area_normalized = true;
  o.open_retries = 0;
  return o;
}

TEST(PoissonFaithful, EstimatedAreaIsTheSurfaceAreaInCubeUnits) {
  // Sphere of radius 0.5 (area pi) in a cube 3.2 x its extent 1.
  const double expect = kPi / (3.2 * 3.2);
  for (int n : {2000, 20000}) {
    const double a = EstimatePoissonSampleArea(SpherePoints(n), 3.2, 10);
    // PoissonRecon's own estimate is 1.07-1.37x the true area on such clouds.
    EXPECT_GT(a / expect, 1.0) << n << " points: " << a << " vs " << expect;
    EXPECT_LT(a / expect, 1.5) << n << " points: " << a << " vs " << expect;
  }
  // Twice the radius: four times the area, same cube ratio -> same cube-unit
  // area; the estimate is scale-free.
  const double a1 = EstimatePoissonSampleArea(SpherePoints(5000, 0.5), 3.2, 10);
  const double a2 = EstimatePoissonSampleArea(SpherePoints(5000, 1.0), 3.2, 10);
  EXPECT_NEAR(a1, a2, 1e-12 + 1e-9 * a1);
}

TEST(PoissonFaithful, EstimatedAreaIgnoresClusteredDuplicates) {
  // RFTA's clouds are clustered (up to n_max points per sphere): piling 3000
  // extra points onto one cap must not change the covered area much, while a
  // count-based normalisation (PCL's) would see 60 % more points.
  PointCloud pc = SpherePoints(5000);
  const double before = EstimatePoissonSampleArea(pc, 3.2, 10);
  PointCloud more;
  more.P.resize(8000, 3);
  more.N.resize(8000, 3);
  more.P.topRows(5000) = pc.P;
  more.N.topRows(5000) = pc.N;
  Rng rng(3);
  for (int i = 5000; i < 8000; ++i) {
    const Vec3 d = Vec3(0.1 * rng.Normal(), 0.1 * rng.Normal(), 1.0).normalized();
    more.N.row(i) = d;
    more.P.row(i) = 0.5 * d;
  }
  const double after = EstimatePoissonSampleArea(more, 3.2, 10);
  EXPECT_NEAR(after / before, 1.0, 0.1) << before << " -> " << after;
}

TEST(PoissonFaithful, OfficialSettingsGiveAClosedSphereOnTheSphere) {
  if (!PoissonAvailable()) GTEST_SKIP() << "arcs was built without PCL (libpcl-dev)";
  const Mesh m = ReconstructPoisson(SpherePoints(3000), Official(), Context());
  const Topology t = ComputeTopology(m);
  EXPECT_TRUE(t.closed);
  EXPECT_EQ(t.components, 1);
  EXPECT_EQ(t.genus, 0);
  double worst = 0;
  for (int v = 0; v < m.NumVertices(); ++v) worst = std::max(worst, std::abs(m.V.row(v).norm() - 0.5));
  EXPECT_LT(worst, 0.01);
}

TEST(PoissonFaithful, Open3dBackendIsPoissonRecon) {
  if (!PoissonOpen3dAvailable()) GTEST_SKIP() << "arcs was built without Open3D (libopen3d-dev)";
  PoissonOptions o = Official();
  o.backend = PoissonOptions::Backend::kOpen3d;
  o.point_weight = 2;  // the only weight Open3D 0.16 runs
  const PointCloud pc = SpherePoints(3000);
  const Mesh m = ReconstructPoisson(pc, o, Context());
  const Topology t = ComputeTopology(m);
  EXPECT_TRUE(t.closed);
  EXPECT_EQ(t.components, 1);
  EXPECT_EQ(t.genus, 0);
  EXPECT_GT(t.volume, 0.0);  // wound outward
  double worst = 0;
  for (int v = 0; v < m.NumVertices(); ++v) worst = std::max(worst, std::abs(m.V.row(v).norm() - 0.5));
  EXPECT_LT(worst, 0.01);
}

// PoissonRecon's own estimate of the sample area (read from Open3D's log),
// against ours, on uniform and clustered clouds of a sphere and a torus.
TEST(PoissonFaithful, EstimatedAreaFollowsPoissonRecons) {
  if (!PoissonOpen3dAvailable()) GTEST_SKIP() << "arcs was built without Open3D (libopen3d-dev)";
  auto clustered = [](PointCloud pc) {
    const Eigen::Index n = pc.P.rows(), extra = n / 2;
    pc.P.conservativeResize(n + extra, 3);
    pc.N.conservativeResize(n + extra, 3);
    Rng rng(3);
    for (Eigen::Index i = n; i < n + extra; ++i) {  // jittered copies of the first tenth
      const Eigen::Index j = i % (n / 10);
      pc.P.row(i) = pc.P.row(j) + 0.003 * Eigen::RowVector3d(rng.Normal(), rng.Normal(), rng.Normal());
      pc.N.row(i) = pc.N.row(j);
    }
    return pc;
  };
  for (int c = 0; c < 4; ++c) {
    const PointCloud pc = c == 0 ? SpherePoints(3000) : c == 1 ? SpherePoints(20000) : clustered(SpherePoints(3000 * c));
    std::vector<double> xyz, nrm;
    for (int i = 0; i < pc.Size(); ++i)
      for (int k = 0; k < 3; ++k) xyz.push_back(pc.P(i, k)), nrm.push_back(pc.N(i, k));
    const auto r = poisson_detail::RunOpen3dPoisson(xyz, nrm, 10, 3.2, 1, true);
    ASSERT_GT(r.estimated_area, 0.0) << "Open3D's 'Estimated Area' log line was not captured";
    const double ours = EstimatePoissonSampleArea(pc, 3.2, 10);
    std::printf("cloud %d (%d points): ours %.4f, PoissonRecon %.4f, ratio %.3f, true %.4f\n", c, pc.Size(), ours,
                r.estimated_area, ours / r.estimated_area, kPi / (3.2 * 3.2));
    EXPECT_NEAR(ours / r.estimated_area, 1.0, 0.25) << "ours " << ours << ", PoissonRecon " << r.estimated_area;
  }
}

}  // namespace
}  // namespace arcs
