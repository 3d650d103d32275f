// The fine-tuner (paper Alg. 3) with a stand-in reconstructor: on exact
// samples of a ball, the "reconstruction" is the ball of radius = mean point
// distance to the centre, so the tuned points must stay on their spheres,
// feasible, within n_max per sphere, and converge to the true surface.
#include "framework/geometry/builtin_shapes.h"
#include "framework/rfta/arc_projector.h"
#include "framework/rfta/fine_tune.h"
#include "framework/rfta/free_space.h"
#include "framework/util/parallel.h"
#include "tests/framework/rfta/rfta_test_shapes.h"

#include <gtest/gtest.h>

namespace arcs {
namespace {

constexpr double kR = 0.3;

Mesh FitBall(const PointCloud& pc) {
  double r = 0;
  for (int i = 0; i < pc.Size(); ++i) r += pc.P.row(i).norm();
  return MakeIcosphere(r / pc.Size(), 4);
}

struct BallCase {
  SdfSamples samples = rfta_test::BallSdfGrid(12, kR);
  ArcProjection a0;
  BallCase() {
    Context ctx(3);
    const FreeSpaceSamples free = RasterizeFreeSpace(samples, RasterizeOptions{}, ctx, nullptr);
    a0 = ProjectToArcs(samples, free, ArcProjectorOptions{}, ctx);
  }
};

TEST(FineTune, PointsStayOnTheirSpheresFeasibleAndNearTheSurface) {
  BallCase s;
  FineTuneOptions o;
  o.iterations = 4;
  o.max_points_per_sphere = 3;
  const FineTuneResult r = FineTune(s.samples, s.a0.points, s.a0.sample, FitBall, o, Context(5));
  ASSERT_EQ(r.iterations.size(), 4u);
  ASSERT_GT(r.points.Size(), 0);
  std::vector<int> count(s.samples.Size(), 0);
  double max_surface = 0;
  for (int j = 0; j < r.points.Size(); ++j) {
    const int i = r.sample[j];
    ++count[i];
    const Vec3 x = r.points.P.row(j).transpose();
    const Vec3 p = s.samples.points.row(i).transpose();
    EXPECT_NEAR((x - p).norm(), std::abs(s.samples.values[i]), 1e-9) << "point " << j << " left its sphere";
    // Feasible: no sphere contains it by more than the tolerance (unit frame tol 1e-4, extent 1 here).
    for (int k = 0; k < s.samples.Size(); ++k) {
      if (k == i) continue;
      const double depth = std::abs(s.samples.values[k]) - (x - Vec3(s.samples.points.row(k).transpose())).norm();
      ASSERT_LT(depth, 2e-4) << "point " << j << " inside sphere " << k;
    }
    max_surface = std::max(max_surface, std::abs(x.norm() - kR));
    // Outward unit normals (eq. 2): radial for a ball.
    EXPECT_NEAR(r.points.N.row(j).norm(), 1.0, 1e-9);
    EXPECT_GT(r.points.N.row(j).dot(r.points.P.row(j)), 0.0);
  }
  for (int c : count) EXPECT_LE(c, 3);
  EXPECT_LT(max_surface, 0.1 / 12) << "tangency points should lie near the true sphere";
}

TEST(FineTune, SameResultAtOneAndTwoThreads) {
  BallCase s;
  FineTuneOptions o;
  o.iterations = 3;
  FineTuneResult a, b;
  {
    ThreadLimit l(1);
    a = FineTune(s.samples, s.a0.points, s.a0.sample, FitBall, o, Context(7));
  }
  {
    ThreadLimit l(2);
    b = FineTune(s.samples, s.a0.points, s.a0.sample, FitBall, o, Context(7));
  }
  ASSERT_EQ(a.points.Size(), b.points.Size());
  EXPECT_EQ((a.points.P - b.points.P).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(a.sample, b.sample);
}

TEST(FineTune, FailingReconstructorStopsEarlyAndKeepsThePoints) {
  BallCase s;
  FineTuneOptions o;
  o.iterations = 5;
  int calls = 0;
  const PointsToMesh flaky = [&](const PointCloud& pc) {
    if (++calls == 3) throw Error("solver exploded");
    return FitBall(pc);
  };
  const FineTuneResult r = FineTune(s.samples, s.a0.points, s.a0.sample, flaky, o, Context(1));
  EXPECT_TRUE(r.stopped_early);
  EXPECT_NE(r.stop_reason.find("solver exploded"), std::string::npos);
  EXPECT_EQ(r.iterations.size(), 2u);
  EXPECT_GT(r.points.Size(), 0);
}

TEST(FineTune, BadInputIsAClearError) {
  BallCase s;
  std::vector<int> wrong = s.a0.sample;
  wrong.pop_back();
  EXPECT_THROW(FineTune(s.samples, s.a0.points, wrong, FitBall, FineTuneOptions{}, Context(1)), Error);
  FineTuneOptions bad;
  bad.max_points_per_sphere = 0;
  EXPECT_THROW(FineTune(s.samples, s.a0.points, s.a0.sample, FitBall, bad, Context(1)), OptionError);
  SdfSamples positive = s.samples;
  positive.values = positive.values.cwiseAbs().array() + 0.01;
  EXPECT_THROW(FineTune(positive, s.a0.points, s.a0.sample, FitBall, FineTuneOptions{}, Context(1)), Error);
}

// Points inside another sphere (as batches leave them): the final check
// against all spheres drops (the default) or repairs them; off keeps
// them (the paper) and counts them.
TEST(FineTune, FinalCheckRemovesOrRepairsPointsInsideOtherSpheres) {
  BallCase s;
  // Every point as projected, plus, for some outside spheres, the far side of
  // the sphere (away from the ball): deep inside the spheres farther out.
  PointCloud pc = s.a0.points;
  std::vector<int> sample = s.a0.sample;
  std::vector<Vec3> extra;
  std::vector<int> extra_sample;
  for (int i = 0; i < s.samples.Size() && extra.size() < 40; i += 7) {
    const Vec3 p = s.samples.points.row(i).transpose();
    const double v = s.samples.values[i];
    if (v < 0.05 || p.norm() > 0.4) continue;
    extra.push_back(p + v * p.normalized());
    extra_sample.push_back(i);
  }
  ASSERT_GE(extra.size(), 10u);
  const int n0 = pc.Size();
  pc.P.conservativeResize(n0 + static_cast<int>(extra.size()), 3);
  pc.N.conservativeResize(n0 + static_cast<int>(extra.size()), 3);
  for (size_t k = 0; k < extra.size(); ++k) {
    pc.P.row(n0 + k) = extra[k].transpose();
    pc.N.row(n0 + k) = extra[k].normalized().transpose();
    sample.push_back(extra_sample[k]);
  }
  auto max_depth = [&](const FineTuneResult& r) {
    double worst = -1;
    for (int j = 0; j < r.points.Size(); ++j) {
      const Vec3 x = r.points.P.row(j).transpose();
      for (int k = 0; k < s.samples.Size(); ++k) {
        if (k == r.sample[j]) continue;
        worst = std::max(worst, std::abs(s.samples.values[k]) - (x - Vec3(s.samples.points.row(k).transpose())).norm());
      }
    }
    return worst;
  };
  FineTuneOptions o;
  o.iterations = 0;
  o.final_check = FineTuneOptions::FinalCheck::kOff;
  const FineTuneResult off = FineTune(s.samples, pc, sample, FitBall, o, Context(3));
  EXPECT_EQ(off.points.Size(), pc.Size());
  EXPECT_GT(max_depth(off), 0.05) << "the far-side points are deep inside other spheres";
  // off measures the violators and keeps them.
  EXPECT_EQ(off.final_infeasible_before, static_cast<std::int64_t>(extra.size()));
  EXPECT_EQ(off.final_infeasible, static_cast<std::int64_t>(extra.size()));
  EXPECT_EQ(off.final_repaired + off.final_dropped, 0);

  o.final_check = FineTuneOptions::FinalCheck::kDrop;
  EXPECT_EQ(FineTuneOptions{}.final_check, FineTuneOptions::FinalCheck::kRepair) << "the default (issue 10, criterion 4)";
  const FineTuneResult drop = FineTune(s.samples, pc, sample, FitBall, o, Context(3));
  EXPECT_EQ(drop.final_infeasible_before, static_cast<std::int64_t>(extra.size()));
  EXPECT_EQ(drop.final_repaired, 0);
  EXPECT_EQ(drop.final_dropped, static_cast<std::int64_t>(extra.size()));
  EXPECT_EQ(drop.final_infeasible, 0);
  EXPECT_EQ(drop.points.Size(), n0);
  EXPECT_LT(max_depth(drop), 2e-4);

  o.final_check = FineTuneOptions::FinalCheck::kRepair;
  const FineTuneResult rep = FineTune(s.samples, pc, sample, FitBall, o, Context(3));
  EXPECT_EQ(rep.final_infeasible_before, static_cast<std::int64_t>(extra.size()));
  EXPECT_GT(rep.final_repaired, 0);
  EXPECT_EQ(rep.final_repaired + rep.final_dropped, static_cast<std::int64_t>(extra.size()));
  EXPECT_EQ(rep.final_infeasible, 0);
  EXPECT_EQ(rep.points.Size(), n0 + rep.final_repaired);
  EXPECT_LT(max_depth(rep), 2e-4);
  for (int j = 0; j < rep.points.Size(); ++j) {
    const int i = rep.sample[j];
    EXPECT_NEAR((rep.points.P.row(j) - s.samples.points.row(i)).norm(), std::abs(s.samples.values[i]), 1e-9);
  }
}

}  // namespace
}  // namespace arcs
