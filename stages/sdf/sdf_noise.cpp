// sdf_noise: Gaussian noise on the SDF values (paper §5.3, Fig. 23).
#include "framework/sdf/sdf_sampling.h"
#include "stages/builtin.h"

namespace arcs {

void RegisterSdfNoise(Registry& r) {
  StageInfo s;
  s.name = "sdf_noise";
  s.role = Role::kSdfModifier;
  s.doc = "adds Gaussian noise N(0, sigma^2) to every SDF value (paper Fig. 23), seeded";
  s.params.Double("sigma", 0.01, "noise standard deviation, in the normalised mesh's units", 0.0);
  s.factory = FunctionStage([](Context& ctx, CaseData& d, const ParamMap& p) {
    d.RequireSamples("sdf_noise");
    AddGaussianNoise(&*d.samples, p.GetDouble("sigma"), ctx.StreamSeed("sdf_noise"));
  });
  r.Register(std::move(s));
}

}  // namespace arcs
