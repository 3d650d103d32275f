// rejection: uniform free-space samples by rejection (the baseline of the RFTA
// paper's Fig. 10), per sign.
#include "framework/rfta/free_space.h"
#include "stages/builtin.h"

namespace arcs {

void RegisterRejection(Registry& r) {
  StageInfo s;
  s.name = "rejection";
  s.role = Role::kEmptySpaceSampler;
  s.doc = "RFTA free-space samples: uniform points outside all spheres of each sign (paper Fig. 10 baseline)";
  s.params.Int("count", 100000, "free points wanted per sign", 1, 1000000000)
      .Double("shrink", 0.95, "covered if |x-c|^2 <= shrink*r^2 (as the rasteriser)", 1e-6, 1.0)
      .Int("max_draws", 50000000, "uniform draws per sign before giving up with fewer points", 1);
  s.factory = FunctionStage([](Context& ctx, CaseData& d, const ParamMap& p) {
    RejectionOptions o;
    o.count = p.GetInt("count");
    o.shrink = p.GetDouble("shrink");
    o.max_draws = std::max(p.GetInt("max_draws"), o.count);
    FreeSpaceSamples f = RejectionFreeSpace(d.RequireSamples("rejection"), o, ctx);
    d.free_points = PointCloud{std::move(f.points), MatrixX3d()};
    d.free_point_sign = std::move(f.sign);
    d.SetMetric("free_points", static_cast<double>(d.free_points->Size()));
  });
  r.Register(std::move(s));
}

}  // namespace arcs
