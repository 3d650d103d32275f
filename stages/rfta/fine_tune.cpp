// fine_tune: the local–global fine-tuning of Reach for the Arcs (paper §4.2,
// Alg. 3). Reads CaseData::points/point_sample (from arc_projector), writes
// the tuned points back; the reconstructor it tunes against is a nested stage.
// On 2D samples it tunes against closed polylines (framework/rfta/fine_tune.h): the 3D
// `screened_poisson` becomes `screened_poisson_2d` (stages/reconstruct/screened_poisson_2d.h).
#include "framework/rfta/fine_tune.h"
#include "framework/rfta/reach_for_the_arcs.h"
#include "stages/builtin.h"
#include "stages/reconstruct/screened_poisson_2d.h"

namespace arcs {

void RegisterFineTune(Registry& r) {
  StageInfo s;
  s.name = "fine_tune";
  s.role = Role::kFineTuner;
  s.doc = "RFTA fine-tuning (paper §4.2, Alg. 3): points move towards the reconstructed surface, up to n_max per sphere";
  s.params.Int("iterations", 10, "k_max fine-tuning iterations (paper default 10; Table 1/2 runs 20)", 0, 10000)
      .Int("max_points_per_sphere", 3, "n_max tangency points per sphere (paper default 3; Table 1/2 runs 30)", 1, 1000)
      .Int("batch_size", 10000, "b constraint spheres per iteration, drawn without replacement (0 = all)", 0,
           1000000000)
      .Double("tau", 0.01, "geodesic step towards the target, in [0,1]-normalised units (paper: 10^-2)", 1e-9, 0.5)
      .Double("severe_ratio", 0.8, "|t| < ratio*|s| is a severe intersection: a point may be added (paper: 4/5)", 1e-6, 1.0)
      .Int("local_search_iters", 20, "make-feasible steps per point (paper Alg. 2: 20)", 0, 1000)
      .Int("local_searches", 0, "k_search containing spheres per step; 0 = ceil(2 N^(1/d)) (paper §4.1)", 0, 100000)
      .Double("tol", 1e-4, "containment/tangency tolerance in [0,1]-normalised units (official 1e-4)", 0.0, 0.05)
      .Choice("pair_choice", "closest", {"closest", "first"},
              "Alg. 2 candidate rule: closest admissible (paper line 13) or first pair (official code)")
      .Bool("jump_when_blocked", true,
            "no feasible step: jump to the target and repair it by Alg. 2 (official) instead of staying")
      .Bool("keep_points_when_missed", false,
            "spheres the surface misses keep all their points (false: only the moved one, paper Alg. 3)")
      .Choice("final_check", "off", {"off", "drop", "repair"},
              "after the last iteration, points inside any sphere (all of them, not a batch) by more than tol: "
              "kept (off, the paper), dropped, or repaired by Alg. 2 against all spheres (dropped if that fails)")
      .Stage("reconstructor", "reconstructor", "screened_poisson",
             "surface reconstructor the points are tuned against (paper: screened Poisson)");
  s.factory = FunctionStage([](Context& ctx, CaseData& d, const ParamMap& p) {
    const SdfSamples& samples = d.RequireSamples("fine_tune");
    if (!d.points) throw Error("fine_tune: needs tangency points; put arc_projector before it");
    FineTuneOptions o;
    o.iterations = static_cast<int>(p.GetInt("iterations"));
    o.max_points_per_sphere = static_cast<int>(p.GetInt("max_points_per_sphere"));
    o.batch_size = p.GetInt("batch_size");
    o.tau = p.GetDouble("tau");
    o.severe_ratio = p.GetDouble("severe_ratio");
    o.local_search_iters = static_cast<int>(p.GetInt("local_search_iters"));
    o.local_searches = static_cast<int>(p.GetInt("local_searches"));
    o.tol = p.GetDouble("tol");
    o.jump_when_blocked = p.GetBool("jump_when_blocked");
    o.keep_points_when_missed = p.GetBool("keep_points_when_missed");
    {
      const std::string fc = p.GetString("final_check");
      o.final_check = fc == "drop"     ? FineTuneOptions::FinalCheck::kDrop
                      : fc == "repair" ? FineTuneOptions::FinalCheck::kRepair
                                       : FineTuneOptions::FinalCheck::kOff;
    }
    o.pair_choice = p.GetString("pair_choice") == "first" ? PairChoice::kFirst : PairChoice::kClosest;
    auto record = [&](FineTuneResult res) {
      d.points = std::move(res.points);
      d.point_sample = std::move(res.sample);
      d.SetMetric("rfta_points", static_cast<double>(d.points->Size()));
      d.SetMetric("fine_tune_iterations", static_cast<double>(res.iterations.size()));
      if (o.final_check != FineTuneOptions::FinalCheck::kOff) {
        d.SetMetric("final_infeasible", static_cast<double>(res.final_infeasible));
        d.SetMetric("final_repaired", static_cast<double>(res.final_repaired));
      }
      double rec_s = 0;
      for (const auto& it : res.iterations) rec_s += it.reconstruct_s;
      d.SetMetric("fine_tune_reconstruct_s", rec_s);
      if (res.stopped_early) ctx.Warn("fine_tune stopped early: " + res.stop_reason);
    };
    const StageSpec& rec = p.GetStage("reconstructor");
    if (samples.dim == 2) {
      const StageSpec rec2 = PlanarReconstructorFor(rec, d.registry);
      const PointsToCurve reconstruct2 = [&](const PointCloud& pc) {
        CaseData sub;
        sub.registry = d.registry;
        sub.points = pc;
        RunNestedStage(rec2, ctx, sub);
        if (!sub.output_curve)
          throw Error("reconstructor '" + rec2.stage + "' produced no 2D curve (2D samples need a 2D reconstructor, "
                      "e.g. screened_poisson_2d)");
        return *sub.output_curve;
      };
      FineTuneResult res = FineTune2D(samples, *d.points, d.point_sample, reconstruct2, o, ctx);
      record(std::move(res));
      return;
    }
    PointsToMesh reconstruct = [&](const PointCloud& pc) {
      CaseData sub;
      sub.registry = d.registry;
      sub.points = pc;
      RunNestedStage(rec, ctx, sub);
      if (!sub.output) throw Error("reconstructor '" + rec.stage + "' produced no mesh");
      return *sub.output;
    };
    record(FineTune(samples, *d.points, d.point_sample, reconstruct, o, ctx));
  });
  r.Register(std::move(s));
}

}  // namespace arcs
