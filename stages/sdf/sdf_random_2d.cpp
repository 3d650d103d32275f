// sdf_random_2d: the exact 2D SDF of the case's reference curve at seeded
// uniform points of a square.
#include "framework/sdf/sdf2d.h"
#include "stages/builtin.h"
#include "stages/curve_inputs.h"

namespace arcs {

namespace {

void RunSdfRandom2D(Context& ctx, CaseData& d, const ParamMap& p) {
  d.samples = SampleSdfRandom2D(RequireReferenceCurve(d, "sdf_random_2d"), p.GetInt("count"), p.GetDouble("lo"),
                                p.GetDouble("hi"), ctx);
}

}  // namespace

void RegisterSdfRandom2D(Registry& r) {
  StageInfo s = DeclareStage("sdf_random_2d", Role::kSdfSampler,
                             "2D SDF of the reference curve at `count` uniform points of [lo,hi]^2 (seeded)",
                             {Slot::kReference}, {Slot::kSamples}, k2D);
  s.params.Int("count", 441, "number of samples (441 = as many as a 20-cell grid)", 1, 100000000)
      .Double("lo", -1.0, "lower box bound on both axes")
      .Double("hi", 1.0, "upper box bound on both axes");
  s.factory = FunctionStage(RunSdfRandom2D);
  r.Register(std::move(s));
}

}  // namespace arcs
