// metropolis_hastings: free-space samples concentrated near the spheres' union
// boundary by random-walk Metropolis–Hastings (the RFTA paper's Fig. 10
// comparison), per sign.
#include "framework/rfta/free_space.h"
#include "registry/bind.h"
#include "stages/builtin.h"

namespace arcs {

namespace {

Binder<MetropolisOptions> MetropolisParams() {
  using O = MetropolisOptions;
  return Binder<O>()
      .Int("count", &O::count, "free points wanted per sign", Closed(1, 1000000000))
      .Double("shrink", &O::shrink, "covered if |x-c|^2 <= shrink*r^2 (as the rasteriser)", LeftOpen(0.0, 1.0))
      .Double("sigma", &O::sigma,
              "target length scale in unit-box units; 0 = a quarter sample spacing 1/(4 N^(1/d))", Closed(0.0, 1.0))
      .Double("step", &O::step, "proposal standard deviation in unit-box units; 0 = sigma", Closed(0.0, 1.0))
      .Int("chains", &O::chains, "independent chains", Closed(1, 1 << 20))
      .Int("burn_in", &O::burn_in, "steps per chain before recording", AtLeast(0))
      .Int("max_steps", &O::max_steps, "steps per chain; 0 = burn_in + 50*count/chains", AtLeast(0));
}

void RunMetropolis(Context& ctx, CaseData& d, const MetropolisOptions& o, const ParamMap&) {
  FreeSpaceSamples f = MetropolisFreeSpace(*d.samples, o, ctx);
  d.free_points = PointCloud{std::move(f.points), MatrixX3d()};
  d.free_point_sign = std::move(f.sign);
  d.SetMetric("free_points", static_cast<double>(d.free_points->Size()));
}

}  // namespace

void RegisterMetropolisHastings(Registry& r) {
  StageInfo s = DeclareStage("metropolis_hastings", Role::kEmptySpaceSampler,
                             "RFTA free-space samples: MH chains with density exp(-d/sigma) near the spheres (paper Fig. 10)",
                             {Slot::kSamples}, {Slot::kFreePoints});
  BindStage<MetropolisOptions>(s, MetropolisParams(), RunMetropolis);
  r.Register(std::move(s));
}

}  // namespace arcs
