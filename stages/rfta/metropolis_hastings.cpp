// metropolis_hastings: free-space samples concentrated near the spheres' union
// boundary by random-walk Metropolis–Hastings (the RFTA paper's Fig. 10
// comparison), per sign.
#include "framework/rfta/free_space.h"
#include "stages/builtin.h"

namespace arcs {

void RegisterMetropolisHastings(Registry& r) {
  StageInfo s;
  s.name = "metropolis_hastings";
  s.role = Role::kEmptySpaceSampler;
  s.doc = "RFTA free-space samples: MH chains with density exp(-d/sigma) near the spheres (paper Fig. 10)";
  s.params.Int("count", 100000, "free points wanted per sign", 1, 1000000000)
      .Double("shrink", 0.95, "covered if |x-c|^2 <= shrink*r^2 (as the rasteriser)", 1e-6, 1.0)
      .Double("sigma", 0.0, "target length scale in unit-box units; 0 = a quarter sample spacing 1/(4 N^(1/d))", 0.0, 1.0)
      .Double("step", 0.0, "proposal standard deviation in unit-box units; 0 = sigma", 0.0, 1.0)
      .Int("chains", 64, "independent chains", 1, 1 << 20)
      .Int("burn_in", 200, "steps per chain before recording", 0)
      .Int("max_steps", 0, "steps per chain; 0 = burn_in + 50*count/chains", 0);
  s.factory = FunctionStage([](Context& ctx, CaseData& d, const ParamMap& p) {
    MetropolisOptions o;
    o.count = p.GetInt("count");
    o.shrink = p.GetDouble("shrink");
    o.sigma = p.GetDouble("sigma");
    o.step = p.GetDouble("step");
    o.chains = static_cast<int>(p.GetInt("chains"));
    o.burn_in = static_cast<int>(p.GetInt("burn_in"));
    o.max_steps = p.GetInt("max_steps");
    FreeSpaceSamples f = MetropolisFreeSpace(d.RequireSamples("metropolis_hastings"), o, ctx);
    d.free_points = PointCloud{std::move(f.points), MatrixX3d()};
    d.free_point_sign = std::move(f.sign);
    d.SetMetric("free_points", static_cast<double>(d.free_points->Size()));
  });
  r.Register(std::move(s));
}

}  // namespace arcs
