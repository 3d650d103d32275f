// arc_projector: the RFTA paper's initial tangency set (§4.1, Supplemental
// Algorithms 1–2): closest free point -> sphere, made feasible; eq. (2) normals.
#include "framework/rfta/arc_projector.h"
#include "registry/bind.h"
#include "stages/builtin.h"
#include "stages/rfta/rfta_params.h"

namespace arcs {

namespace {

Binder<ArcProjectorOptions> ArcProjectorParams() {
  using O = ArcProjectorOptions;
  return Binder<O>()
      .Group(&O::search, FeasibleSearchParams(), {"local_search_iters", "local_searches", "tol"})
      .Int("batch_size", &O::batch_size, "constraint spheres per sign, drawn without replacement (paper b; 0 = all)",
           AtLeast(0))
      .Group(&O::search, FeasibleSearchParams(), {"pair_choice"});
}

void RunArcProjector(Context& ctx, CaseData& d, const ArcProjectorOptions& o, const ParamMap&) {
  FreeSpaceSamples f;
  f.points = d.free_points->P;
  f.sign = d.free_point_sign;
  ArcProjection a = ProjectToArcs(*d.samples, f, o, ctx);
  ctx.Info("arc_projector: " + std::to_string(a.points.Size()) + " points (" +
           std::to_string(a.stats.feasible_at_projection) + " feasible at projection, " +
           std::to_string(a.stats.made_feasible) + " made feasible, " + std::to_string(a.stats.dropped) +
           " dropped)");
  d.points = std::move(a.points);
  d.point_sample = std::move(a.sample);
  d.SetMetric("arc_points", static_cast<double>(d.points->Size()));
  d.SetMetric("arc_dropped", static_cast<double>(a.stats.dropped));
}

}  // namespace

void RegisterArcProjector(Registry& r) {
  StageInfo s = DeclareStage(
      "arc_projector", Role::kArcProjector,
      "RFTA initial tangency points: closest free point projected onto each sphere, made feasible (Alg. 2)",
      {Slot::kSamples, Slot::kFreePoints}, {Slot::kPoints});
  BindStage<ArcProjectorOptions>(s, ArcProjectorParams(), RunArcProjector);
  r.Register(std::move(s));
}

}  // namespace arcs
