// sdf_noise: Gaussian noise on the SDF values (paper §5.3, Fig. 23).
#include "framework/sdf/sdf_sampling.h"
#include "registry/bind.h"
#include "stages/builtin.h"

namespace arcs {

namespace {

Binder<SdfNoiseOptions> SdfNoiseParams() {
  using O = SdfNoiseOptions;
  return Binder<O>().Double("sigma", &O::sigma, "noise standard deviation, in the normalised mesh's units",
                            AtLeast(0.0));
}

void RunSdfNoise(Context& ctx, CaseData& d, const SdfNoiseOptions& o, const ParamMap&) {
  AddGaussianNoise(&*d.samples, o.sigma, ctx.StreamSeed("sdf_noise"));
}

}  // namespace

void RegisterSdfNoise(Registry& r) {
  StageInfo s = DeclareStage("sdf_noise", Role::kSdfModifier,
                             "adds Gaussian noise N(0, sigma^2) to every SDF value (paper Fig. 23), seeded",
                             {Slot::kSamples}, {Slot::kSamples}, kAnyDim);
  BindStage<SdfNoiseOptions>(s, SdfNoiseParams(), RunSdfNoise);
  r.Register(std::move(s));
}

}  // namespace arcs
