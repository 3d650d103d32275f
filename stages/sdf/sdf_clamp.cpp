// sdf_clamp: a clamped (truncated) SDF (paper §5.3, Fig. 24).
#include "framework/sdf/sdf_sampling.h"
#include "registry/bind.h"
#include "stages/builtin.h"

namespace arcs {

namespace {

Binder<SdfClampOptions> SdfClampParams() {
  using O = SdfClampOptions;
  return Binder<O>().Double("clamp", &O::clamp, "clamp value (> 0), in the normalised mesh's units", Above(0.0));
}

void RunSdfClamp(Context&, CaseData& d, const SdfClampOptions& o, const ParamMap&) {
  ClampSdf(&*d.samples, o.clamp);
}

}  // namespace

void RegisterSdfClamp(Registry& r) {
  StageInfo s = DeclareStage("sdf_clamp", Role::kSdfModifier,
                             "clamps SDF values to [-clamp, clamp] and marks the samples as clamped (paper Fig. 24)",
                             {Slot::kSamples}, {Slot::kSamples}, kAnyDim);
  BindStage<SdfClampOptions>(s, SdfClampParams(), RunSdfClamp);
  r.Register(std::move(s));
}

}  // namespace arcs
