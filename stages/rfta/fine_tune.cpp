// fine_tune: the local–global fine-tuning of Reach for the Arcs (paper §4.2,
// Alg. 3). Reads CaseData::points/point_sample (from arc_projector), writes
// the tuned points back; the reconstructor it tunes against is a nested stage.
// On 2D samples it tunes against closed polylines (framework/rfta/fine_tune.h): the 3D
// `screened_poisson` becomes `screened_poisson_2d` (stages/reconstruct/screened_poisson_2d.h).
#include "framework/rfta/fine_tune.h"
#include "framework/rfta/reach_for_the_arcs.h"
#include "registry/bind.h"
#include "stages/reconstruct/screened_poisson_spec.h"
#include "stages/builtin.h"
#include "stages/reconstruct/screened_poisson_2d.h"
#include "stages/rfta/rfta_params.h"

namespace arcs {

namespace {

Binder<FineTuneOptions> FineTuneParams() {
  using O = FineTuneOptions;
  Binder<O> b;
  b.Int("iterations", &O::iterations, "k_max fine-tuning iterations (paper default 10; Table 1/2 runs 20)",
        Closed(0, 10000))
      .Int("max_points_per_sphere", &O::max_points_per_sphere,
           "n_max tangency points per sphere (paper default 3; Table 1/2 runs 30)", Closed(1, 1000))
      .Int("batch_size", &O::batch_size, "b constraint spheres per iteration, drawn without replacement (0 = all)",
           Closed(0, 1000000000))
      .Double("tau", &O::tau, "geodesic step towards the target, in [0,1]-normalised units (paper: 10^-2)",
              Open(0.0, 1.0))
      .Double("severe_ratio", &O::severe_ratio,
              "|t| < ratio*|s| is a severe intersection: a point may be added (paper: 4/5)", LeftOpen(0.0, 1.0))
      .Group(&O::search, FeasibleSearchParams())
      .Bool("jump_when_blocked", &O::jump_when_blocked,
            "no feasible step: jump to the target and repair it by Alg. 2 (official) instead of staying")
      .Bool("keep_points_when_missed", &O::keep_points_when_missed,
            "spheres the surface misses keep all their points (false: only the moved one, paper Alg. 3)");
  FinalCheckParam(b).Stage("reconstructor", "reconstructor", RftaTuningPoissonSpec(),
                           "surface reconstructor the points are tuned against (paper: screened Poisson; default "
                           "rfta's tuning surfaces: the official call's geometry and solver, normal_splat split, "
                           "density_scale 1, point_weight 10; warm-started from the previous iteration)");
  return b;
}

void RunFineTune(Context& ctx, CaseData& d, const FineTuneOptions& o, const ParamMap& p) {
  const SdfSamples& samples = *d.samples;
  auto record = [&](FineTuneResult res) {
    d.points = std::move(res.points);
    d.point_sample = std::move(res.sample);
    d.SetMetric("rfta_points", static_cast<double>(d.points->Size()));
    d.SetMetric("fine_tune_iterations", static_cast<double>(res.iterations.size()));
    SetFinalCheckMetrics(d, res);
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
  NestedState carry;  // the reconstructor's state from one iteration to the next (warm start)
  PointsToMesh reconstruct = [&](const PointCloud& pc) {
    CaseData sub;
    sub.registry = d.registry;
    sub.points = pc;
    RunNestedStage(rec, ctx, sub, &carry);
    if (!sub.output) throw Error("reconstructor '" + rec.stage + "' produced no mesh");
    return *sub.output;
  };
  record(FineTune(samples, *d.points, d.point_sample, reconstruct, o, ctx));
}

}  // namespace

void RegisterFineTune(Registry& r) {
  StageInfo s = DeclareStage(
      "fine_tune", Role::kFineTuner,
      "RFTA fine-tuning (paper §4.2, Alg. 3): points move towards the reconstructed surface, up to n_max per sphere",
      {Slot::kSamples, Slot::kPoints}, {Slot::kPoints});
  BindStage<FineTuneOptions>(s, FineTuneParams(), RunFineTune);
  r.Register(std::move(s));
}

}  // namespace arcs
