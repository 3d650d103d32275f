// rfta: Reach for the Arcs as one SDF -> mesh stage (paper Alg. 1): an
// empty-space sampler, the arc projector, the fine-tuner and the final
// reconstruction, each the registered stage of that name, so `rfta` and the
// explicit pipeline give the same result. Writes the time of each part.
// On 2D samples (dim 2) it writes CaseData::output_curve: the reconstructors
// `screened_poisson` (the 3D default, final and tuning) become
// `screened_poisson_2d` with its defaults (stages/reconstruct/screened_poisson_2d.h); a
// configured 2D reconstructor is used as given.
#include "framework/rfta/sphere_set.h"
#include "registry/registry.h"
#include "stages/builtin.h"
#include "stages/reconstruct/screened_poisson_2d.h"

#include <chrono>

namespace arcs {

void RegisterRfta(Registry& r) {
  StageInfo s;
  s.name = "rfta";
  s.role = Role::kSdfToMesh;
  s.doc = "Reach for the Arcs (paper Alg. 1): free-space sampling, arc projection, fine-tuning, reconstruction";
  s.params.Stage("sampler", "empty_space_sampler", "rasterize", "empty-space sampler (paper: rasterize)")
      .Int("iterations", 10, "k_max fine-tuning iterations (paper default 10; Table 1/2 runs 20)", 0, 10000)
      .Int("max_points_per_sphere", 3, "n_max tangency points per sphere (paper default 3; Table 1/2 runs 30)", 1, 1000)
      .Int("batch_size", 10000, "b constraint spheres, drawn without replacement (paper 10 000; 0 = all)", 0,
           1000000000)
      .Stage("reconstructor", "reconstructor", "screened_poisson",
             "surface reconstructor of the final mesh (paper: screened Poisson)")
      .Stage("tuning_reconstructor", "reconstructor", [] {
               StageSpec coarse;
               coarse.stage = "screened_poisson";
               coarse.params.Set("depth_offset", std::int64_t{-3});
               coarse.params.Set("samples_per_node", 4.0);
               coarse.params.Set("open_retries", std::int64_t{0});
               return coarse;
             }(),
             "reconstructor inside fine-tuning: screened Poisson three octree levels coarser than the final, "
             "at least 4 points per leaf, no re-solve of open surfaces (these surfaces only steer the points; "
             "bunny_fixed n=20 paper preset: 17.3 s, Chamfer 0.0177, against 26.2 s, 0.0166 at 1.5 points "
             "per leaf; official 227 s, 0.0219)")
      .Choice("final_check", "off", {"off", "drop", "repair"},
              "fine_tune's check of the tuned points against all spheres before the final reconstruction "
              "(off: the paper; drop / repair: see fine_tune)")
      .Choice("on_sign_conflict", "warn", {"warn", "error", "ignore"},
              "positive and negative spheres that overlap (not an SDF; noisy SDFs, Fig. 23, have some): "
              "warn and go on (refused when more than half of the outside spheres conflict), fail the case, "
              "or say nothing and go on");
  s.factory = FunctionStage([](Context& ctx, CaseData& d, const ParamMap& p) {
    if (!d.registry) throw Error("rfta: needs the case's registry");
    const Registry& reg = *d.registry;
    using Clock = std::chrono::steady_clock;
    auto timed = [&](const char* metric, const StageSpec& spec) {
      const auto t0 = Clock::now();
      RunNestedStage(spec, ctx, d);
      d.SetMetric(metric, std::chrono::duration<double>(Clock::now() - t0).count());
    };
    ParamMap proj;
    proj.Set("batch_size", p.GetInt("batch_size"));
    ParamMap ft;
    ft.Set("iterations", p.GetInt("iterations"));
    ft.Set("max_points_per_sphere", p.GetInt("max_points_per_sphere"));
    ft.Set("batch_size", p.GetInt("batch_size"));
    ft.Set("final_check", p.GetString("final_check"));
    ft.Set("reconstructor", p.Get("tuning_reconstructor"));
    {
      const SdfSamples& samples = d.RequireSamples("rfta");
      CheckRftaSamples(samples, "rfta");
      const SignedSpheres spheres = SplitSpheresBySign(samples, SignSplitOptions{});
      RequireBothSigns(spheres, "rfta");
      double depth = 0;
      const std::int64_t conflicts = CountSignConflicts(spheres, 1e-4, &depth);
      d.SetMetric("rfta_sign_conflicts", static_cast<double>(conflicts));
      if (conflicts > 0 && p.GetString("on_sign_conflict") != "ignore") {
        const std::string msg = "rfta: " + std::to_string(conflicts) + " of " + std::to_string(spheres.positive.Size()) +
                                " outside spheres overlap inside spheres (deepest overlap " +
                                std::to_string(depth * spheres.frame.scale) +
                                "): the samples are not a consistent SDF";
        if (p.GetString("on_sign_conflict") == "error") throw Error(msg);
        // Noisy SDFs have some conflicts; when most outside spheres conflict
        // the samples are no SDF at all (e.g. mesh distances signed by an
        // open-mesh shell) and RFTA would spend minutes on nothing.
        if (2 * conflicts > spheres.positive.Size())
          throw Error(msg + "; more than half of the outside spheres conflict: refused "
                            "(on_sign_conflict: ignore goes on anyway)");
        ctx.Warn(msg + "; going on (set on_sign_conflict: error to refuse such input)");
      }
    }
    const bool planar = d.RequireSamples("rfta").dim == 2;
    timed("rfta_sampler_s", p.GetStage("sampler"));
    timed("rfta_projector_s", StageSpec{"arc_projector", reg.Resolve("arc_projector", proj)});
    timed("rfta_fine_tune_s", StageSpec{"fine_tune", reg.Resolve("fine_tune", ft)});
    if (planar) {
      d.output_curve.reset();
      timed("rfta_final_s", PlanarReconstructorFor(p.GetStage("reconstructor"), d.registry));
      if (!d.output_curve) throw Error("rfta: the reconstructor produced no 2D curve (2D samples need a 2D reconstructor, e.g. screened_poisson_2d)");
      if (d.output_curve->Empty()) throw Error("rfta: the final 2D reconstruction is empty");
      return;
    }
    timed("rfta_final_s", p.GetStage("reconstructor"));
    if (!d.output) throw Error("rfta: the reconstructor produced no mesh");
  });
  r.Register(std::move(s));
}

}  // namespace arcs
