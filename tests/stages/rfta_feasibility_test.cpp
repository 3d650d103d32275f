// Issue 10, criterion 4: the final points of Reach for the Arcs violate no
// sphere (all of them, not a batch) by more than tol, unless final_check says
// off; the count of violators is a metric of the case in every mode.
//
// The case: the built-in torus at n = 14 (15^3 = 3 375 samples) with a batch
// of 200 spheres, so that batching leaves points inside spheres outside their
// batch (at the default b = 10 000 every sphere is in every batch up to n = 20
// and there would be nothing to check). The violators are counted here, by brute
// force against every sample's sphere in the input frame, independently of
// the sphere trees the stages use.
#include "framework/geometry/builtin_shapes.h"
#include "framework/geometry/normalize.h"
#include "framework/sdf/sdf_sampling.h"
#include "registry/registry.h"
#include "stages/builtin.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace arcs {
namespace {

constexpr double kTol = 1e-4;  // the stages' default tol (unit frame)

SdfSamples TorusSamples(int n) {
  Mesh torus = MakeTorus();
  Normalize(&torus, NormalizeOptions{});
  SdfGridOptions go;
  go.n = n;
  return SampleSdfGrid(torus, go, Context(1));
}

double Metric(const CaseData& d, const std::string& name) {
  for (const auto& [k, v] : d.metrics)
    if (k == name) return v;
  ADD_FAILURE() << "no metric " << name;
  return -1;
}

// Points of `d` inside the sphere of some sample other than their own by more
// than `tol_factor` * tol (tol in the unit frame: the samples' largest extent
// is 1).
std::int64_t CountViolators(const SdfSamples& s, const CaseData& d, double tol_factor) {
  double scale = 0;
  for (int a = 0; a < 3; ++a) scale = std::max(scale, s.points.col(a).maxCoeff() - s.points.col(a).minCoeff());
  const double tol = tol_factor * kTol * scale;
  const PointCloud& pc = *d.points;
  std::int64_t count = 0;
  for (int j = 0; j < pc.Size(); ++j) {
    const Vec3 x = pc.P.row(j).transpose();
    for (std::int64_t k = 0; k < s.Size(); ++k) {
      if (k == d.point_sample[j]) continue;
      if (std::abs(s.values[k]) - (x - Vec3(s.points.row(k).transpose())).norm() > tol) {
        ++count;
        break;
      }
    }
  }
  return count;
}

ParamMap SmallBatch(const std::string& final_check) {
  ParamMap p;
  p.Set("batch_size", std::int64_t{200});
  p.Set("iterations", std::int64_t{3});
  if (!final_check.empty()) p.Set("final_check", final_check);
  return p;
}

CaseData RunRfta(const Registry& r, const SdfSamples& s, const ParamMap& given) {
  CaseData d;
  d.registry = &r;
  d.samples = s;
  Context ctx(7);
  r.Get("rfta").factory(r.Resolve("rfta", given))->Run(ctx, d);
  return d;
}

// The explicit pipeline's parts: rasterize, arc_projector (batch 200), then
// the fine_tune stage with `given`.
CaseData RunFineTuneStage(const Registry& r, const SdfSamples& s, const ParamMap& given) {
  CaseData d;
  d.registry = &r;
  d.samples = s;
  Context ctx(7);
  auto run = [&](const std::string& name, const ParamMap& p) { r.Get(name).factory(r.Resolve(name, p))->Run(ctx, d); };
  run("rasterize", ParamMap());
  ParamMap ap;
  ap.Set("batch_size", std::int64_t{200});
  run("arc_projector", ap);
  run("fine_tune", given);
  return d;
}

TEST(RftaFeasibility, BothStagesShareTheDefault) {
  Registry r;
  RegisterBuiltinStages(r);
  const std::string def = r.Resolve("fine_tune", ParamMap()).GetString("final_check");
  EXPECT_EQ(def, "repair");
  EXPECT_EQ(r.Resolve("rfta", ParamMap()).GetString("final_check"), def);
}

// rfta: with the default no final point violates any sphere (counted here);
// with off the metric is the independent count, and there are violators to
// count (otherwise the case would test nothing).
TEST(RftaFeasibility, RftaDefaultLeavesNoViolatorAndOffCountsThem) {
  Registry r;
  RegisterBuiltinStages(r);
  const SdfSamples s = TorusSamples(14);

  const CaseData off = RunRfta(r, s, SmallBatch("off"));
  const std::int64_t off_lo = CountViolators(s, off, 1.0 + 1e-6), off_hi = CountViolators(s, off, 1.0 - 1e-6);
  ASSERT_GT(off_lo, 0) << "batches of 200 of 3375 spheres should leave violators";
  EXPECT_GE(Metric(off, "final_infeasible"), off_lo);
  EXPECT_LE(Metric(off, "final_infeasible"), off_hi);
  EXPECT_EQ(Metric(off, "final_infeasible_before"), Metric(off, "final_infeasible"));
  EXPECT_EQ(Metric(off, "final_repaired"), 0);
  EXPECT_EQ(Metric(off, "final_dropped"), 0);

  const CaseData def = RunRfta(r, s, SmallBatch(""));
  EXPECT_EQ(CountViolators(s, def, 1.0 + 1e-6), 0);
  EXPECT_EQ(Metric(def, "final_infeasible"), 0);
  // The same iterations (same seed) as off, then the check fixed them.
  EXPECT_EQ(Metric(def, "final_infeasible_before"), Metric(off, "final_infeasible"));
  EXPECT_EQ(Metric(def, "final_repaired") + Metric(def, "final_dropped"), Metric(def, "final_infeasible_before"));
  EXPECT_EQ(Metric(def, "rfta_points"), Metric(off, "rfta_points") - Metric(def, "final_dropped"));
  ASSERT_TRUE(def.output.has_value());
  EXPECT_GT(def.output->NumFaces(), 0);
}

// The fine_tune stage on its own: the same guarantee and the same metric.
TEST(RftaFeasibility, FineTuneStageDefaultLeavesNoViolatorAndOffCountsThem) {
  Registry r;
  RegisterBuiltinStages(r);
  const SdfSamples s = TorusSamples(14);
  ParamMap off_p, def_p, rep_p, drop_p;
  off_p.Set("batch_size", std::int64_t{200});
  off_p.Set("iterations", std::int64_t{3});
  def_p = off_p;
  rep_p = off_p;
  drop_p = off_p;
  off_p.Set("final_check", std::string("off"));
  rep_p.Set("final_check", std::string("repair"));
  drop_p.Set("final_check", std::string("drop"));

  const CaseData off = RunFineTuneStage(r, s, off_p);
  const std::int64_t off_lo = CountViolators(s, off, 1.0 + 1e-6), off_hi = CountViolators(s, off, 1.0 - 1e-6);
  ASSERT_GT(off_lo, 0);
  EXPECT_GE(Metric(off, "final_infeasible"), off_lo);
  EXPECT_LE(Metric(off, "final_infeasible"), off_hi);
  EXPECT_EQ(off.points->Size(), static_cast<int>(Metric(off, "rfta_points")));

  const CaseData def = RunFineTuneStage(r, s, def_p);
  EXPECT_EQ(CountViolators(s, def, 1.0 + 1e-6), 0);
  EXPECT_EQ(Metric(def, "final_infeasible"), 0);
  EXPECT_EQ(Metric(def, "final_infeasible_before"), Metric(off, "final_infeasible"));

  const CaseData drop = RunFineTuneStage(r, s, drop_p);
  EXPECT_EQ(CountViolators(s, drop, 1.0 + 1e-6), 0);
  EXPECT_EQ(Metric(drop, "final_infeasible"), 0);
  EXPECT_EQ(Metric(drop, "final_dropped"), Metric(off, "final_infeasible"));  // drop: every violator goes
  EXPECT_EQ(Metric(drop, "final_repaired"), 0);
  EXPECT_EQ(drop.points->Size(), off.points->Size() - static_cast<int>(Metric(off, "final_infeasible")));

  const CaseData rep = RunFineTuneStage(r, s, rep_p);
  EXPECT_EQ(CountViolators(s, rep, 1.0 + 1e-6), 0);
  EXPECT_EQ(Metric(rep, "final_infeasible"), 0);
  EXPECT_GT(Metric(rep, "final_repaired"), 0);
  EXPECT_EQ(Metric(rep, "final_repaired") + Metric(rep, "final_dropped"), Metric(off, "final_infeasible"));
  EXPECT_EQ(rep.points->Size(), off.points->Size() - static_cast<int>(Metric(rep, "final_dropped")));
  // The default is repair: the same points and counts.
  EXPECT_EQ(def.points->Size(), rep.points->Size());
  EXPECT_EQ(Metric(def, "final_repaired"), Metric(rep, "final_repaired"));
  EXPECT_EQ(Metric(def, "final_dropped"), Metric(rep, "final_dropped"));
  EXPECT_TRUE(def.points->P == rep.points->P);
}

}  // namespace
}  // namespace arcs
