#include "framework/sdfmesh/vdb_mesher.h"

#include "framework/error.h"
#include "framework/spatial/topology.h"
#include "framework/util/parallel.h"
#include "tests/framework/sdfmesh/sdfmesh_test_fields.h"

#include <gtest/gtest.h>

#include <cmath>

namespace arcs {
namespace {

using testing::BoxSdf;
using testing::GridSamples;
using testing::SphereSdf;
using testing::TorusSdf;

#define REQUIRE_OPENVDB() \
  if (!VdbMesherAvailable()) GTEST_SKIP() << "built without OpenVDB (libopenvdb-dev)"

TEST(VdbMesherTest, SphereIsClosedOutwardAndOnTheSurface) {
  REQUIRE_OPENVDB();
  const double r = 0.6;
  const SdfSamples s = GridSamples(20, -1, 1, [&](const Vec3& p) { return SphereSdf(p, r); });
  const Mesh m = VdbVolumeToMesh(s.values, *s.grid);
  const Topology t = ComputeTopology(m);
  EXPECT_TRUE(t.closed);
  EXPECT_EQ(t.genus, 0);
  EXPECT_GT(t.volume, 0.0) << "faces must be wound outward";
  EXPECT_NEAR(t.volume, 4.0 / 3.0 * M_PI * r * r * r, 0.05 * 4.0 / 3.0 * M_PI * r * r * r);
  double err = 0;
  for (int v = 0; v < m.NumVertices(); ++v) err = std::max(err, std::abs(m.V.row(v).norm() - r));
  EXPECT_LT(err, 0.05);  // half a cell: the mean of the crossings lies inside the cell, near the sphere
}

TEST(VdbMesherTest, PlacementFollowsTheGridFrame) {
  REQUIRE_OPENVDB();
  // An off-centre sphere on an anisotropic, shifted grid.
  SdfSamples s;
  GridInfo g;
  g.dims = {21, 17, 13};
  g.min = {0.0, -2.0, 1.0};
  g.max = {2.0, 0.0, 3.0};
  const Vec3 c(1.1, -0.9, 2.05);
  s.points.resize(g.NumNodes(), 3);
  s.values.resize(g.NumNodes());
  for (int k = 0; k < g.dims[2]; ++k)
    for (int j = 0; j < g.dims[1]; ++j)
      for (int i = 0; i < g.dims[0]; ++i) {
        const Vec3 p(g.min[0] + i * g.Spacing(0), g.min[1] + j * g.Spacing(1), g.min[2] + k * g.Spacing(2));
        s.values[i + g.dims[0] * (j + g.dims[1] * k)] = SphereSdf(p, 0.6, c);
      }
  const Mesh m = VdbVolumeToMesh(s.values, g);
  EXPECT_GT(ComputeTopology(m).volume, 0.0);
  const Vec3 centroid = m.V.colwise().mean().transpose();
  EXPECT_LT((centroid - c).norm(), 0.05);
}

TEST(VdbMesherTest, AdaptivityMergesFlatRegions) {
  REQUIRE_OPENVDB();
  const SdfSamples s = GridSamples(40, -1, 1, [](const Vec3& p) { return BoxSdf(p, Vec3(0.5, 0.4, 0.3)); });
  VdbMesherOptions o;
  const int uniform = VdbVolumeToMesh(s.values, *s.grid, o).NumFaces();
  o.adaptivity = 0.9;
  const Mesh adapted = VdbVolumeToMesh(s.values, *s.grid, o);
  EXPECT_LT(adapted.NumFaces(), uniform / 2);
  EXPECT_GT(ComputeTopology(adapted).volume, 0.0);
}

TEST(VdbMesherTest, SameMeshAtOneAndTwoThreads) {
  REQUIRE_OPENVDB();
  const SdfSamples s = GridSamples(30, -1, 1, [](const Vec3& p) { return TorusSdf(p, 0.45, 0.18); });
  Mesh a, b;
  {
    ThreadLimit l(1);
    a = VdbVolumeToMesh(s.values, *s.grid);
  }
  {
    ThreadLimit l(2);
    b = VdbVolumeToMesh(s.values, *s.grid);
  }
  EXPECT_EQ(a.V, b.V);
  EXPECT_EQ(a.F, b.F);
  EXPECT_EQ(ComputeTopology(a).genus, 1);
}

TEST(VdbMesherTest, BadInputIsAClearError) {
  const SdfSamples s = GridSamples(4, -1, 1, [](const Vec3& p) { return SphereSdf(p, 0.5); });
  VectorXd v = s.values;
  v[2] = NAN;
  EXPECT_THROW(VdbVolumeToMesh(v, *s.grid), Error);
  EXPECT_THROW(VdbVolumeToMesh(s.values.head(5), *s.grid), Error);
  VdbMesherOptions o;
  o.adaptivity = 1.5;
  EXPECT_THROW(VdbVolumeToMesh(s.values, *s.grid, o), OptionError);
}

}  // namespace
}  // namespace arcs
