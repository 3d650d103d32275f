// arc_projector: the RFTA paper's initial tangency set (§4.1, Supplemental
// Algorithms 1–2): closest free point -> sphere, made feasible; eq. (2) normals.
#include "framework/rfta/arc_projector.h"
#include "stages/builtin.h"

namespace arcs {

void RegisterArcProjector(Registry& r) {
  StageInfo s;
  s.name = "arc_projector";
  s.role = Role::kArcProjector;
  s.doc = "RFTA initial tangency points: closest free point projected onto each sphere, made feasible (Alg. 2)";
  s.params.Int("local_search_iters", 20, "make-feasible steps per point (paper Alg. 2: 20)", 0, 10000)
      .Int("local_searches", 0, "k_search: containing spheres gathered per step; 0 = ceil(2 N^(1/d)) (paper §4.1)", 0, 100000)
      .Double("tol", 1e-4, "containment tolerance in unit-box units (official 1e-4)", 0.0, 0.1)
      .Int("batch_size", 10000, "constraint spheres per sign, drawn without replacement (paper b; 0 = all)", 0)
      .Choice("pair_choice", "closest", {"closest", "first"},
              "with >= 2 containing spheres: closest admissible point over all pairs (paper Alg. 2) or first pair by radius (official; can cycle)");
  s.factory = FunctionStage([](Context& ctx, CaseData& d, const ParamMap& p) {
    ArcProjectorOptions o;
    o.local_search_iters = static_cast<int>(p.GetInt("local_search_iters"));
    o.local_searches = static_cast<int>(p.GetInt("local_searches"));
    o.tol = p.GetDouble("tol");
    o.batch_size = p.GetInt("batch_size");
    o.pair_choice = p.GetString("pair_choice") == "closest" ? PairChoice::kClosest : PairChoice::kFirst;
    const SdfSamples& samples = d.RequireSamples("arc_projector");
    if (!d.free_points)
      throw Error("arc_projector: no free-space samples; put an empty_space_sampler stage "
                  "(rasterize, rejection, metropolis_hastings) before it");
    FreeSpaceSamples f;
    f.points = d.free_points->P;
    f.sign = d.free_point_sign;
    ArcProjection a = ProjectToArcs(samples, f, o, ctx);
    ctx.Info("arc_projector: " + std::to_string(a.points.Size()) + " points (" +
             std::to_string(a.stats.feasible_at_projection) + " feasible at projection, " +
             std::to_string(a.stats.made_feasible) + " made feasible, " + std::to_string(a.stats.dropped) +
             " dropped)");
    d.points = std::move(a.points);
    d.point_sample = std::move(a.sample);
    d.SetMetric("arc_points", static_cast<double>(d.points->Size()));
    d.SetMetric("arc_dropped", static_cast<double>(a.stats.dropped));
  });
  r.Register(std::move(s));
}

}  // namespace arcs
