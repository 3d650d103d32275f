// Mesh morphing (Luo et al. §2.4) on small analytic targets.
#include "framework/context.h"
#include "framework/error.h"
#include "framework/geometry/builtin_shapes.h"
#include "framework/util/parallel.h"
#include "framework/voxel/morph.h"
#include "framework/voxel/voxelize.h"

#include <gtest/gtest.h>

#include <cstdlib>

namespace arcs {
namespace {

// An ellipsoid with a smaller sphere fused to its side (two overlapping closed
// meshes: w ≥ 1 in the overlap, still inside for w > 0.5), on a res³ grid.
VolumeGrid BlobTarget(int res) {
  Mesh e = MakeIcosphere(1.0, 3);
  for (int i = 0; i < e.NumVertices(); ++i) {
    e.V(i, 0) *= 0.36;
    e.V(i, 1) *= 0.22;
    e.V(i, 2) *= 0.2;
  }
  const Mesh s = MakeIcosphere(0.16, 3, Vec3(0.3, 0.14, 0.02));
  VolumeGrid t;
  t.info = CubeGrid(res, Vec3::Constant(-0.55), Vec3::Constant(0.55));
  t.values = HardOccupancy(Concatenate({e, s}), t.info);
  return t;
}

MorphOptions TestOptions() {
  MorphOptions o;
  o.iterations = 60;
  o.batch = 3000;
  o.refresh_every = 10;
  return o;
}

TEST(MorphTest, SphereToBlobIoURisesAboveThreshold) {
  const VolumeGrid target = BlobTarget(24);
  const Mesh src = InitialSphere(target, 3);
  Context ctx(3);
  MorphOptions o = TestOptions();
  if (const char* it = std::getenv("ARCS_MORPH_TEST_ITERS")) o.iterations = std::atoi(it);
  const MorphResult r = MorphToOccupancy(src, target, o, ctx);
  for (const auto& e : r.log)
    std::printf("it %4d  iou %.4f  loss %.5f  active %d  %.2fs\n", e.iteration, e.iou, e.loss, e.active, e.seconds);
  ASSERT_GE(r.log.size(), 3u);
  EXPECT_EQ(r.log.front().iteration, 0);
  EXPECT_EQ(r.log.back().iteration, o.iterations);
  EXPECT_EQ(r.final_iou, r.log.back().iou);
  // The sphere of equal volume already overlaps most of the blob; morphing
  // must close most of the remaining gap.
  EXPECT_LT(r.initial_iou, 0.8);
  EXPECT_GT(r.final_iou, 0.9);
  EXPECT_GT(r.final_iou, r.initial_iou + 0.1);
  EXPECT_EQ(r.mesh.NumFaces(), src.NumFaces());
  EXPECT_TRUE(r.mesh.V.allFinite());
}

TEST(MorphTest, SameMeshAtOneAndTwoThreads) {
  const VolumeGrid target = BlobTarget(16);
  const Mesh src = InitialSphere(target, 2);
  MorphOptions o = TestOptions();
  o.iterations = 20;
  o.batch = 1000;
  MorphResult a, b;
  {
    ThreadLimit l(1);
    Context ctx(5);
    a = MorphToOccupancy(src, target, o, ctx);
  }
  {
    ThreadLimit l(2);
    Context ctx(5);
    b = MorphToOccupancy(src, target, o, ctx);
  }
  EXPECT_TRUE((a.mesh.V.array() == b.mesh.V.array()).all());
  EXPECT_EQ(a.final_iou, b.final_iou);
}

TEST(MorphTest, InitialSphereHasTheTargetsVolumeAndCentre) {
  VolumeGrid t;
  t.info = CubeGrid(40, Vec3::Constant(-1), Vec3::Constant(1));
  t.values = HardOccupancy(MakeIcosphere(0.5, 4, Vec3(0.2, -0.1, 0.05)), t.info);
  const Mesh s = InitialSphere(t, 3);
  const Vec3 c = s.V.colwise().mean().transpose();
  EXPECT_NEAR(c.x(), 0.2, 0.01);
  EXPECT_NEAR(c.y(), -0.1, 0.01);
  EXPECT_NEAR(c.z(), 0.05, 0.01);
  EXPECT_NEAR(s.V.row(0).norm() > 0 ? (s.V.row(0).transpose() - c).norm() : 0.0, 0.5, 0.02);
  EXPECT_GT(OccupancyIoU(HardOccupancy(s, t.info), t.values), 0.95);
}

TEST(MorphTest, LaplacianEnergyGradientMatchesDifferences) {
  Mesh m = MakeIcosphere(0.5, 1);
  for (int i = 0; i < m.NumVertices(); ++i) m.V(i, i % 3) += 0.01 * (i % 5);
  MatrixX3d g;
  UniformLaplacianEnergy(m, &g);
  const double h = 1e-6;
  for (int i = 0; i < m.NumVertices(); i += 7)
    for (int k = 0; k < 3; ++k) {
      Mesh p = m, q = m;
      p.V(i, k) += h;
      q.V(i, k) -= h;
      const double fd = (UniformLaplacianEnergy(p, nullptr) - UniformLaplacianEnergy(q, nullptr)) / (2 * h);
      EXPECT_NEAR(fd, g(i, k), 1e-7 * (1 + std::abs(g(i, k))));
    }
}

TEST(MorphTest, BadInputIsAClearError) {
  const VolumeGrid target = BlobTarget(8);
  Context ctx;
  MorphOptions o;
  o.lr = -1;
  EXPECT_THROW(o.Check(), OptionError);
  EXPECT_THROW(MorphToOccupancy(Mesh{}, target, {}, ctx), Error);
  VolumeGrid empty = target;
  empty.values.setZero();
  EXPECT_THROW(InitialSphere(empty, 2), Error);
  VolumeGrid wrong = target;
  wrong.values.resize(5);
  EXPECT_THROW(MorphToOccupancy(MakeIcosphere(0.2, 1), wrong, {}, ctx), Error);
  EXPECT_THROW(CubeGrid(1, Vec3::Constant(0), Vec3::Constant(1)), OptionError);
}

}  // namespace
}  // namespace arcs
