// The RFTA stages through the registry: empty-space samplers feed the arc
// projector on the exact SDF of a ball.
#include "registry/registry.h"
#include "stages/builtin.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace arcs {
namespace {

// (n+1)^3 grid on [-0.5, 0.5]^3, exact SDF of the ball of radius R at 0.
SdfSamples Ball(int n, double R) {
  SdfSamples s;
  s.dim = 3;
  const int m = n + 1;
  s.points.resize(static_cast<std::int64_t>(m) * m * m, 3);
  s.values.resize(s.points.rows());
  std::int64_t t = 0;
  for (int k = 0; k < m; ++k)
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i, ++t) {
        const Vec3 p(-0.5 + 1.0 * i / n, -0.5 + 1.0 * j / n, -0.5 + 1.0 * k / n);
        s.points.row(t) = p.transpose();
        s.values[t] = p.norm() - R;
      }
  return s;
}

void RunStage(const Registry& r, const std::string& name, const ParamMap& given, Context& ctx, CaseData& d) {
  const ParamMap p = r.Resolve(name, given);
  r.Get(name).factory(p)->Run(ctx, d);
}

double Metric(const CaseData& d, const std::string& name) {
  for (const auto& [k, v] : d.metrics)
    if (k == name) return v;
  ADD_FAILURE() << "no metric " << name;
  return -1;
}

TEST(RftaStages, RegisteredWithRoles) {
  Registry r;
  RegisterBuiltinStages(r);
  EXPECT_EQ(r.Get("rasterize").role, Role::kEmptySpaceSampler);
  EXPECT_EQ(r.Get("rejection").role, Role::kEmptySpaceSampler);
  EXPECT_EQ(r.Get("metropolis_hastings").role, Role::kEmptySpaceSampler);
  EXPECT_EQ(r.Get("arc_projector").role, Role::kArcProjector);
  // Paper / official defaults.
  const ParamMap p = r.Resolve("arc_projector", ParamMap());
  EXPECT_EQ(p.GetInt("local_search_iters"), 20);
  EXPECT_EQ(p.GetInt("batch_size"), 10000);
  EXPECT_DOUBLE_EQ(p.GetDouble("tol"), 1e-4);
  EXPECT_DOUBLE_EQ(r.Resolve("rasterize", ParamMap()).GetDouble("shrink"), 0.95);
  ParamMap bad;
  bad.Set("shrink", 2.0);
  EXPECT_THROW(r.Resolve("rasterize", bad), OptionError);
}

TEST(RftaStages, EachSamplerFeedsTheProjector) {
  Registry r;
  RegisterBuiltinStages(r);
  for (const std::string sampler : {"rasterize", "rejection", "metropolis_hastings"}) {
    Context ctx(1);
    CaseData d;
    d.samples = Ball(12, 0.3);
    ParamMap sp;
    if (sampler != "rasterize") sp.Set("count", std::int64_t{20000});
    RunStage(r, sampler, sp, ctx, d);
    ASSERT_TRUE(d.free_points.has_value()) << sampler;
    ASSERT_EQ(static_cast<int>(d.free_point_sign.size()), d.free_points->Size());
    EXPECT_GT(Metric(d, "free_points"), 1000);
    // The positive spheres' free space is the ball's inside, the negative
    // ones' its outside, up to the pockets the shrunk spheres leave on the
    // other side of the surface (sizeable on this coarse grid).
    int pos = 0, pos_inside = 0, neg_outside = 0;
    for (int j = 0; j < d.free_points->Size(); ++j) {
      const signed char s = d.free_point_sign[j];
      ASSERT_TRUE(s == 1 || s == -1);
      const bool inside = d.free_points->P.row(j).norm() < 0.3;
      pos += s > 0;
      pos_inside += s > 0 && inside;
      neg_outside += s < 0 && !inside;
    }
    EXPECT_GT(pos, 0);
    EXPECT_LT(pos, d.free_points->Size());
    EXPECT_GT(pos_inside, 0.75 * pos) << sampler;  // rasterize: 86% at this coarse grid
    EXPECT_GT(neg_outside, 0.75 * (d.free_points->Size() - pos)) << sampler;
    RunStage(r, "arc_projector", ParamMap(), ctx, d);
    ASSERT_TRUE(d.points.has_value());
    ASSERT_EQ(static_cast<int>(d.point_sample.size()), d.points->Size());
    ASSERT_TRUE(d.points->HasNormals());
    EXPECT_EQ(Metric(d, "arc_points"), d.points->Size());
    EXPECT_GT(d.points->Size(), 1500) << sampler;
    double mean_err = 0.0;
    for (int t = 0; t < d.points->Size(); ++t) {
      const Vec3 x = d.points->P.row(t).transpose();
      const int i = d.point_sample[t];
      EXPECT_NEAR((x - Vec3(d.samples->points.row(i).transpose())).norm(), std::abs(d.samples->values[i]), 1e-9);
      mean_err += std::abs(x.norm() - 0.3) / d.points->Size();
    }
    // Grid spacing 1/12: tangency points sit on the ball far closer than that.
    EXPECT_LT(mean_err, 0.1 / 12) << sampler;
  }
}

TEST(RftaStages, ProjectorNeedsFreePoints) {
  Registry r;
  RegisterBuiltinStages(r);
  Context ctx;
  CaseData d;
  d.samples = Ball(6, 0.3);
  EXPECT_THROW(RunStage(r, "arc_projector", ParamMap(), ctx, d), Error);
  CaseData none;
  EXPECT_THROW(RunStage(r, "rasterize", ParamMap(), ctx, none), Error);
}

}  // namespace
}  // namespace arcs
