// sdf_random: SDF at uniformly random points of a box (seeded).
#include "framework/sdf/sdf_sampling.h"
#include "stages/builtin.h"

namespace arcs {

void RegisterSdfRandom(Registry& r) {
  StageInfo s;
  s.name = "sdf_random";
  s.role = Role::kSdfSampler;
  s.doc = "SDF at uniformly random points of the box [lo,hi]^3 (seeded), sign by winding number";
  s.params.Int("count", 10000, "number of samples", 1, 1000000000)
      .Double("lo", -1.0, "lower box bound on every axis")
      .Double("hi", 1.0, "upper box bound on every axis");
  s.factory = FunctionStage([](Context& ctx, CaseData& d, const ParamMap& p) {
    if (!(p.GetDouble("hi") > p.GetDouble("lo"))) throw OptionError("sdf_random: hi must be greater than lo");
    d.samples = SampleSdfRandom(d.RequireReference("sdf_random"), p.GetInt("count"), p.GetDouble("lo"),
                                p.GetDouble("hi"), ctx);
  });
  r.Register(std::move(s));
}

}  // namespace arcs
