// rejection: uniform free-space samples by rejection (the baseline of the RFTA
// paper's Fig. 10), per sign.
#include "framework/rfta/free_space.h"
#include "registry/bind.h"
#include "stages/builtin.h"

#include <algorithm>

namespace arcs {

namespace {

// The stage raises max_draws to count (a budget below the wanted count
// cannot be met), where the algorithm refuses it.
RejectionOptions WithBudget(RejectionOptions o) {
  o.max_draws = std::max(o.max_draws, o.count);
  return o;
}

Binder<RejectionOptions> RejectionParams() {
  using O = RejectionOptions;
  return Binder<O>()
      .Int("count", &O::count, "free points wanted per sign", Closed(1, 1000000000))
      .Double("shrink", &O::shrink, "covered if |x-c|^2 <= shrink*r^2 (as the rasteriser)", LeftOpen(0.0, 1.0))
      .Int("max_draws", &O::max_draws, "uniform draws per sign before giving up with fewer points (at least count)",
           AtLeast(1))
      .Check([](const O& o) {
        ARCS_CHECK_OPTION(o.max_draws >= 1, "max_draws", o.max_draws, ">= 1");
        WithBudget(o).Check();
      });
}

void RunRejection(Context& ctx, CaseData& d, const RejectionOptions& o, const ParamMap&) {
  FreeSpaceSamples f = RejectionFreeSpace(*d.samples, WithBudget(o), ctx);
  d.free_points = PointCloud{std::move(f.points), MatrixX3d()};
  d.free_point_sign = std::move(f.sign);
  d.SetMetric("free_points", static_cast<double>(d.free_points->Size()));
}

}  // namespace

void RegisterRejection(Registry& r) {
  StageInfo s = DeclareStage("rejection", Role::kEmptySpaceSampler,
                             "RFTA free-space samples: uniform points outside all spheres of each sign (paper Fig. 10 baseline)",
                             {Slot::kSamples}, {Slot::kFreePoints});
  BindStage<RejectionOptions>(s, RejectionParams(), RunRejection);
  r.Register(std::move(s));
}

}  // namespace arcs
