// rfta: Reach for the Arcs as one SDF -> mesh stage (paper Alg. 1), a thin
// adaptor over the library's ReachForTheArcs (framework/rfta/
// reach_for_the_arcs.h) for both dimensions. Its parts run as the registered
// stages of the same names: the configured empty-space sampler and
// reconstructors are nested stages (so `rfta` and the explicit pipeline
// [sampler, arc_projector, fine_tune, reconstructor] give the same result),
// and the case data and metrics are written as those stages write them, with
// the time of each part (rfta_*_s).
// On 2D samples (dim 2) it writes CaseData::output_curve: the reconstructors
// `screened_poisson` (the 3D default, final and tuning) become
// `screened_poisson_2d` with its defaults (stages/reconstruct/
// screened_poisson_2d.h); a configured 2D reconstructor is used as given.
#include "framework/rfta/reach_for_the_arcs.h"
#include "registry/registry.h"
#include "stages/builtin.h"
#include "stages/reconstruct/screened_poisson_2d.h"
#include "stages/reconstruct/screened_poisson_spec.h"
#include "stages/rfta/rfta_params.h"

namespace arcs {

namespace {

// The fine_tune stage's options with rfta's parameters (stages/rfta/fine_tune.cpp
// resolves the same defaults).
RftaOptions DecodeRftaOptions(const ParamMap& p) {
  RftaOptions o;
  o.projector.batch_size = p.GetInt("batch_size");
  o.fine_tune.iterations = static_cast<int>(p.GetInt("iterations"));
  o.fine_tune.max_points_per_sphere = static_cast<int>(p.GetInt("max_points_per_sphere"));
  o.fine_tune.batch_size = p.GetInt("batch_size");
  o.fine_tune.final_check = EnumFromName(std::span<const EnumName<FineTuneOptions::FinalCheck>>(
                                              FineTuneOptions::kFinalCheckNames),
                                          p.GetString("final_check"));
  o.projector.search.pair_choice = o.fine_tune.search.pair_choice =
      EnumFromName(std::span<const EnumName<PairChoice>>(kPairChoiceNames), p.GetString("pair_choice"));
  o.drop_infeasible_components = p.GetBool("drop_infeasible_components");
  o.small_components = p.GetDouble("small_components");
  o.tuning_cell = p.GetDouble("tuning_cell");
  o.carve = p.GetBool("carve");
  o.carve_margin = p.GetDouble("carve_margin");
  const std::string sc = p.GetString("on_sign_conflict");
  o.on_sign_conflict = sc == "error"    ? RftaOptions::OnSignConflict::kError
                       : sc == "ignore" ? RftaOptions::OnSignConflict::kIgnore
                                        : RftaOptions::OnSignConflict::kWarn;
  return o;
}

// Runs the reconstructor stage `spec` on `pc` in a case of its own; `carry`
// (optional) takes the stage's state from one call to the next (warm start).
Surface ReconstructBy(const StageSpec& spec, const PointCloud& pc, Context& ctx, const Registry* registry, int dim,
                      NestedState* carry = nullptr) {
  CaseData sub;
  sub.registry = registry;
  sub.points = pc;
  RunNestedStage(spec, ctx, sub, carry);
  if (dim == 2) {
    if (!sub.output_curve)
      throw Error("reconstructor '" + spec.stage + "' produced no 2D curve (2D samples need a 2D reconstructor, "
                  "e.g. screened_poisson_2d)");
    return std::move(*sub.output_curve);
  }
  if (!sub.output) throw Error("reconstructor '" + spec.stage + "' produced no mesh");
  return std::move(*sub.output);
}

void RunRfta(Context& ctx, CaseData& d, const ParamMap& p) {
  if (!d.registry) throw Error("rfta: needs the case's registry");
  const SdfSamples& samples = d.RequireSamples("rfta");
  const int dim = samples.dim;
  const RftaOptions options = DecodeRftaOptions(p);
  StageSpec final_spec =
      dim == 2 ? PlanarReconstructorFor(p.GetStage("reconstructor"), d.registry) : p.GetStage("reconstructor");
  StageSpec tuning_spec = dim == 2 ? PlanarReconstructorFor(p.GetStage("tuning_reconstructor"), d.registry)
                                         : p.GetStage("tuning_reconstructor");
  // tuning_cell: the tuning surfaces' marching cubes no finer than that
  // fraction of the samples' spacing (the nested screened_poisson's
  // extract_max_cell, unless it is set there).
  const double cell = TuningMaxCell(samples, options.tuning_cell);
  if (cell > 0) {
    // Applied only where it means something: screened_poisson with backend
    // arcs, and extract_max_cell not set there already; otherwise said so.
    const bool has = tuning_spec.params.Has("extract_max_cell");
    const bool arcs_backend = tuning_spec.params.Has("backend") && tuning_spec.params.GetString("backend") == "arcs";
    if (has && arcs_backend && tuning_spec.params.GetDouble("extract_max_cell") == 0) {
      tuning_spec.params.Set("extract_max_cell", cell);
      d.SetMetric("rfta_tuning_max_cell", cell);
    } else {
      ctx.Warn("rfta: tuning_cell " + std::to_string(options.tuning_cell) + " ignored: " +
               (!has || !arcs_backend
                    ? "the tuning reconstructor '" + tuning_spec.stage +
                          "' is not screened_poisson with backend arcs (extract_max_cell)"
                    : std::string("the tuning reconstructor's extract_max_cell is set already")));
    }
  }
  // carve: the final screened Poisson carves the outside samples' balls out
  // of its solid (its carve_spheres), where it can.
  if (dim == 3 && options.carve) {
    const bool arcs_backend = final_spec.stage == "screened_poisson" && final_spec.params.Has("backend") &&
                              final_spec.params.GetString("backend") == "arcs";
    if (arcs_backend) {
      final_spec.params.Set("carve_spheres", true);
      final_spec.params.Set("carve_margin", options.carve_margin);
    } else
      ctx.Warn("rfta: carve ignored: the reconstructor '" + final_spec.stage +
               "' is not screened_poisson with backend arcs (carve_spheres)");
  }
  RftaParts parts;
  // The sampler and the final reconstructor run on the case itself (they see
  // all of it and write their metrics and slots); the tuning reconstructor
  // in a case of its own per iteration, as the fine_tune stage runs it.
  parts.sampler = [&](const SdfSamples&, const Context&) {
    RunNestedStage(p.GetStage("sampler"), ctx, d);
    if (!d.free_points)
      throw Error("rfta: the sampler '" + p.GetStage("sampler").stage + "' produced no free-space samples");
    FreeSpaceSamples f;
    f.points = d.free_points->P;
    f.sign = d.free_point_sign;
    return f;
  };
  NestedState carry;
  parts.tuning = [&](const PointCloud& pc) { return ReconstructBy(tuning_spec, pc, ctx, d.registry, dim, &carry); };
  parts.reconstruct = [&](const PointCloud&) -> Surface {
    RunNestedStage(final_spec, ctx, d);
    if (dim == 2) {
      if (!d.output_curve)
        throw Error("rfta: the reconstructor produced no 2D curve (2D samples need a 2D reconstructor, e.g. "
                    "screened_poisson_2d)");
      return std::move(*d.output_curve);
    }
    if (!d.output) throw Error("rfta: the reconstructor produced no mesh");
    return std::move(*d.output);
  };
  // The case data and metrics of each part as its stage writes them.
  parts.after = [&](RftaPart part, const RftaResult& r) {
    switch (part) {
      case RftaPart::kSignCheck:
        d.SetMetric("rfta_sign_conflicts", static_cast<double>(r.sign_conflicts));
        break;
      case RftaPart::kSampler:
        d.SetMetric("rfta_sampler_s", r.sampler_s);
        break;
      case RftaPart::kProjector:  // as stages/rfta/arc_projector.cpp
        ctx.Info("arc_projector: " + std::to_string(r.points.Size()) + " points (" +
                 std::to_string(r.projector.feasible_at_projection) + " feasible at projection, " +
                 std::to_string(r.projector.made_feasible) + " made feasible, " +
                 std::to_string(r.projector.dropped) + " dropped)");
        d.points = r.points;
        d.point_sample = r.sample;
        d.SetMetric("arc_points", static_cast<double>(d.points->Size()));
        d.SetMetric("arc_dropped", static_cast<double>(r.projector.dropped));
        d.SetMetric("rfta_projector_s", r.projector_s);
        break;
      case RftaPart::kFineTune: {  // as stages/rfta/fine_tune.cpp
        d.points = r.points;
        d.point_sample = r.sample;
        d.SetMetric("rfta_points", static_cast<double>(d.points->Size()));
        d.SetMetric("fine_tune_iterations", static_cast<double>(r.tuning.iterations.size()));
        SetFinalCheckMetrics(d, r.tuning);
        double rec_s = 0;
        for (const auto& it : r.tuning.iterations) rec_s += it.reconstruct_s;
        d.SetMetric("fine_tune_reconstruct_s", rec_s);
        if (r.tuning.stopped_early) ctx.Warn("fine_tune stopped early: " + r.tuning.stop_reason);
        d.SetMetric("rfta_fine_tune_s", r.fine_tune_s);
        if (dim == 2) d.output_curve.reset();
        break;
      }
      case RftaPart::kFinal:
        break;
    }
  };
  RftaResult r = ReachForTheArcs(samples, options, parts, ctx);
  if (dim == 2) d.output_curve = std::get<Polyline>(std::move(r.surface));
  else d.output = std::get<Mesh>(std::move(r.surface));
  if (dim == 3 && options.drop_infeasible_components) {
    d.SetMetric("rfta_dropped_components", static_cast<double>(r.components.dropped));
    d.SetMetric("rfta_kept_components_by_fit", static_cast<double>(r.components.kept_by_fit));
  }
  if (dim == 3 && options.small_components > 0)
    d.SetMetric("rfta_dropped_small_components", static_cast<double>(r.small.dropped));
  d.SetMetric("rfta_final_s", r.final_s);
}

}  // namespace

void RegisterRfta(Registry& r) {
  // The parameters are the nested stages' (sampler, reconstructors) and the
  // few it forwards to fine_tune and arc_projector, whose own declarations
  // (and bounds) apply when they run.
  StageInfo s = DeclareStage("rfta", Role::kSdfToMesh,
                             "Reach for the Arcs (paper Alg. 1): free-space sampling, arc projection, fine-tuning, reconstruction",
                             {Slot::kSamples}, {Slot::kFreePoints, Slot::kPoints, Slot::kOutput}, kAnyDim);
  s.params.Stage("sampler", "empty_space_sampler", "rasterize", "empty-space sampler (paper: rasterize)")
      .Int("iterations", 10, "k_max fine-tuning iterations (paper default 10; Table 1/2 runs 20)", 0, 10000)
      .Int("max_points_per_sphere", 3, "n_max tangency points per sphere (paper default 3; Table 1/2 runs 30)", 1, 1000)
      .Int("batch_size", 10000, "b constraint spheres, drawn without replacement (paper 10 000; 0 = all)", 0,
           1000000000)
      .Stage("reconstructor", "reconstructor", OfficialPoissonSpec(),
             "surface reconstructor of the final mesh (paper: screened Poisson; default the official call in full: "
             "arcs' own solver, depth 10, cube 3.2x, 1.5 samples per node, PoissonRecon's weight 10 and sample "
             "placement: point_weight 15, normal_splat ceil, density_scale 1.5; docs/poisson.md)")
      .Stage("tuning_reconstructor", "reconstructor", RftaTuningPoissonSpec(),
             "reconstructor inside fine-tuning (default: the final call's geometry and solver with normal_splat "
             "split, density_scale 1, point_weight 10, a measured deviation: the official code uses the final "
             "call, docs/poisson.md session 39; warm-started from the previous iteration)")
      .Double("tuning_cell", 0.0,
              "3D: when > 0, the tuning surfaces' marching cubes no finer than this fraction of the samples' "
              "spacing (sets the tuning screened_poisson's extract_max_cell; 0 = the final surface's level, "
              "as the official code; docs/rfta_table1.md session 19)",
              0.0, 100.0)
      .Bool("drop_infeasible_components", true,
            "3D: remove final components most of whose vertices lie inside a sample's sphere by more than tol "
            "(ruled out by the samples; not in the paper, the official code keeps them)")
      .Double("small_components", 0.5,
              "3D: remove final components (not the largest) smaller than this fraction of the samples' spacing, "
              "smallest first, while together they add at most (fraction x spacing)^2 to the samples' summed "
              "squared misfit: blobs below the samples' resolution that their fit does not need (0 = keep them, "
              "as the official code; docs/decisions.md)",
              0.0, 10.0)
      .Bool("carve", RftaOptions{}.carve,
            "3D: carve the balls of the samples with s > 0 (less tol) out of the final surface's solid: the "
            "samples certify them empty, and the surface through the tangency points can still cut them "
            "(sheets across hollows, bulges); sets the final screened_poisson's carve_spheres (backend arcs). "
            "Not in the paper, the official code keeps them (docs/decisions.md, \"Carving\")")
      .Double("carve_margin", RftaOptions{}.carve_margin,
              "3D, carve: carve only where a ball is entered by more than this fraction of the samples' spacing "
              "(at least tol)",
              0.0, 10.0);
  // final_check: the fine_tune stage's own declaration (names, default, doc).
  Binder<FineTuneOptions> final_check;
  const ParamSchema final_check_schema = FinalCheckParam(final_check).Schema();
  for (const ParamSpec& spec : final_check_schema.specs()) s.params.Add(spec);
  // pair_choice: Algorithm 2's own declaration, for the projector and the fine-tuner alike.
  s.params.Add(*FeasibleSearchParams().Schema().Find("pair_choice"));
  s.params.Choice("on_sign_conflict", "warn", {"warn", "error", "ignore"},
                  "positive and negative spheres that overlap (not an SDF; noisy SDFs, Fig. 23, have some): "
                  "warn and go on (refused when more than half of the outside spheres conflict), fail the "
                  "case, or say nothing and go on");
  s.factory = FunctionStage(RunRfta);
  r.Register(std::move(s));
}

}  // namespace arcs
