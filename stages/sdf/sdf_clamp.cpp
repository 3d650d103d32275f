// sdf_clamp: a clamped (truncated) SDF (paper §5.3, Fig. 24).
#include "framework/sdf/sdf_sampling.h"
#include "stages/builtin.h"

namespace arcs {

void RegisterSdfClamp(Registry& r) {
  StageInfo s;
  s.name = "sdf_clamp";
  s.role = Role::kSdfModifier;
  s.doc = "clamps SDF values to [-clamp, clamp] and marks the samples as clamped (paper Fig. 24)";
  s.params.Double("clamp", 0.1, "clamp value (> 0), in the normalised mesh's units", 1e-12);
  s.factory = FunctionStage([](Context&, CaseData& d, const ParamMap& p) {
    d.RequireSamples("sdf_clamp");
    ClampSdf(&*d.samples, p.GetDouble("clamp"));
  });
  r.Register(std::move(s));
}

}  // namespace arcs
