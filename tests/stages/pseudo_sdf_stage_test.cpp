// RFTA on a pseudo-SDF (paper §5.3, Fig. 25): a sphere swept along a segment
// (a capsule) sampled as min over poses, whose inside values only bound the
// depth. RFTA must still give a closed surface close to the swept solid,
// and closer than marching cubes on the same grid.
#include "framework/eval/metrics.h"
#include "framework/geometry/builtin_shapes.h"
#include "framework/rfta/sphere_set.h"
#include "framework/spatial/topology.h"
#include "registry/registry.h"
#include "stages/builtin.h"

#include <gtest/gtest.h>

namespace arcs {
namespace {

void RunStage(const Registry& r, const std::string& name, const ParamMap& given, Context& ctx, CaseData& d) {
  r.Get(name).factory(r.Resolve(name, given))->Run(ctx, d);
}

TEST(PseudoSdfStage, BoundSpheresGetNoTangencyPoints) {
  SdfSamples s;
  s.points.resize(4, 3);
  s.points << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  s.values.resize(4);
  s.values << -0.2, 0.3, 0.4, -0.1;
  s.bound_sign = -1;
  const SignedSpheres sp = SplitSpheresBySign(s, SignSplitOptions{});
  for (char w : sp.negative.wants_point) EXPECT_FALSE(w);
  for (char w : sp.positive.wants_point) EXPECT_TRUE(w);
}

TEST(PseudoSdfStage, RftaReconstructsASweptSphere) {
  Registry r;
  RegisterBuiltinStages(r);
  Context ctx(1);
  CaseData d;
  d.registry = &r;
  d.reference = MakeIcosphere(0.2, 3, Vec3(-0.2, 0, 0));
  ParamMap sweep;
  sweep.Set("n", std::int64_t{16});
  sweep.Set("dx", 0.4);
  sweep.Set("steps", std::int64_t{12});
  sweep.Set("reference_n", std::int64_t{40});
  RunStage(r, "sdf_sweep", sweep, ctx, d);
  ASSERT_TRUE(d.samples && d.reference);
  EXPECT_EQ(d.samples->bound_sign, -1);
  RunStage(r, "marching_cubes", ParamMap(), ctx, d);
  const double mc = ChamferPaper(*d.output, *d.reference, 20000, 1);
  d.output.reset();
  RunStage(r, "rfta", ParamMap(), ctx, d);
  ASSERT_TRUE(d.output);
  const Topology t = ComputeTopology(*d.output);
  EXPECT_TRUE(t.closed);
  EXPECT_EQ(t.genus, 0);
  const double rfta = ChamferPaper(*d.output, *d.reference, 20000, 1);
  EXPECT_LT(rfta, mc) << "RFTA " << rfta << " vs MC " << mc;
  EXPECT_LT(rfta, 0.01);
}

}  // namespace
}  // namespace arcs
