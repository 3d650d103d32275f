#include "framework/rfta/reach_for_the_arcs.h"

#include "framework/error.h"
#include "framework/rfta/sphere_carve.h"
#include "framework/rfta/sphere_set.h"

#include <chrono>
#include <cmath>
#include <string>

namespace arcs {

void RftaOptions::Check() const {
  raster.Check();
  projector.Check();
  fine_tune.Check();
  poisson.Check();
  tuning_poisson.Check();
  poisson_2d.Check();
  tuning_poisson_2d.Check();
  ARCS_CHECK_OPTION(std::isfinite(tuning_cell) && tuning_cell >= 0 && tuning_cell <= 100, "tuning_cell", tuning_cell,
                    "in [0, 100]");
  ARCS_CHECK_OPTION(std::isfinite(carve_margin) && carve_margin >= 0 && carve_margin <= 10, "carve_margin",
                    carve_margin, "in [0, 10]");
  ARCS_CHECK_OPTION(std::isfinite(small_components) && small_components >= 0 && small_components <= 10,
                    "small_components", small_components, "in [0, 10]");
}

double TuningMaxCell(const SdfSamples& samples, double tuning_cell) {
  return samples.dim == 3 && tuning_cell > 0 ? tuning_cell * SampleSpacing(samples) : 0.0;
}

SurfaceReconstructor DefaultRftaReconstructor(int dim, const RftaOptions& options, bool tuning, const Context& ctx) {
  if (dim == 2) {
    const Poisson2DOptions o = tuning ? options.tuning_poisson_2d : options.poisson_2d;
    return [o, &ctx](const PointCloud& pc) -> Surface { return ReconstructPoisson2D(pc, o, ctx); };
  }
  const PoissonOptions o = tuning ? options.tuning_poisson : options.poisson;
  // The tuning surfaces are solved again and again for one case: carry the
  // solution from one call to the next (backend arcs warm-starts from it).
  auto state = std::make_shared<std::shared_ptr<void>>();
  return [o, &ctx, state](const PointCloud& pc) -> Surface {
    PoissonOptions r = o;
    r.Check();
    if (r.depth == 0) r.depth = AutoPoissonDepth(pc, r);
    return ReconstructPoisson(pc, r, ctx, nullptr, state.get());
  };
}

namespace {

using Clock = std::chrono::steady_clock;
double Since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// The sign check before any work (paper §3: the spheres of an SDF never
// overlap across the surface).
void CheckSigns(const SdfSamples& samples, const RftaOptions& options, const RftaParts& parts, RftaResult* r,
                const Context& ctx) {
  CheckRftaSamples(samples, "rfta");
  const SignedSpheres spheres = SplitSpheresBySign(samples, SignSplitOptions{});
  RequireBothSigns(spheres, "rfta");
  double depth = 0;
  r->sign_conflicts = CountSignConflicts(spheres, 1e-4, &depth);
  r->sign_conflict_depth = depth * spheres.frame.scale;
  if (parts.after) parts.after(RftaPart::kSignCheck, *r);
  using Policy = RftaOptions::OnSignConflict;
  if (r->sign_conflicts == 0 || options.on_sign_conflict == Policy::kIgnore) return;
  const std::string msg = "rfta: " + std::to_string(r->sign_conflicts) + " of " +
                          std::to_string(spheres.positive.Size()) +
                          " outside spheres overlap inside spheres (deepest overlap " +
                          std::to_string(r->sign_conflict_depth) + "): the samples are not a consistent SDF";
  if (options.on_sign_conflict == Policy::kError) throw Error(msg);
  // Noisy SDFs have some conflicts; when most outside spheres conflict the
  // samples are no SDF at all (e.g. mesh distances signed by an open-mesh
  // shell) and RFTA would spend minutes on nothing.
  if (2 * r->sign_conflicts > spheres.positive.Size())
    throw Error(msg + "; more than half of the outside spheres conflict: refused "
                      "(on_sign_conflict: ignore goes on anyway)");
  ctx.Warn(msg + "; going on (set on_sign_conflict: error to refuse such input)");
}

}  // namespace

RftaResult ReachForTheArcs(const SdfSamples& samples, const RftaOptions& options, const RftaParts& parts,
                           const Context& ctx) {
  options.Check();
  const int dim = samples.dim;
  RftaResult r;
  CheckSigns(samples, options, parts, &r, ctx);
  auto after = [&](RftaPart part) {
    if (parts.after) parts.after(part, r);
  };

  // 1. Free-space samples of each sign (Alg. 1 line 1).
  auto t0 = Clock::now();
  r.free = parts.sampler ? parts.sampler(samples, ctx) : RasterizeFreeSpace(samples, options.raster, ctx, nullptr);
  r.sampler_s = Since(t0);
  after(RftaPart::kSampler);

  // 2. The initial tangency points (lines 2-8).
  t0 = Clock::now();
  {
    ArcProjection a0 = ProjectToArcs(samples, r.free, options.projector, ctx);
    r.points = std::move(a0.points);
    r.sample = std::move(a0.sample);
    r.projector = a0.stats;
  }
  r.projector_s = Since(t0);
  after(RftaPart::kProjector);

  // 3. Fine-tuning against the tuning reconstructor's surfaces (Alg. 3).
  t0 = Clock::now();
  SurfaceReconstructor tuning = parts.tuning;
  if (!tuning) {
    RftaOptions tuned = options;
    if (tuned.tuning_poisson.extract_max_cell == 0)
      tuned.tuning_poisson.extract_max_cell = TuningMaxCell(samples, options.tuning_cell);
    tuning = DefaultRftaReconstructor(dim, tuned, /*tuning=*/true, ctx);
  }
  if (dim == 2) {
    const PointsToCurve curve = [&](const PointCloud& pc) {
      Surface s = tuning(pc);
      if (!std::holds_alternative<Polyline>(s))
        throw Error("rfta: the tuning reconstructor gave a mesh for 2D samples (2D samples need a 2D reconstructor, "
                    "e.g. screened_poisson_2d)");
      return std::get<Polyline>(std::move(s));
    };
    r.tuning = FineTune2D(samples, r.points, r.sample, curve, options.fine_tune, ctx);
  } else {
    const PointsToMesh mesh = [&](const PointCloud& pc) {
      Surface s = tuning(pc);
      if (!std::holds_alternative<Mesh>(s))
        throw Error("rfta: the tuning reconstructor gave a 2D curve for 3D samples");
      return std::get<Mesh>(std::move(s));
    };
    r.tuning = FineTune(samples, r.points, r.sample, mesh, options.fine_tune, ctx);
  }
  r.points = std::move(r.tuning.points);
  r.sample = std::move(r.tuning.sample);
  r.tuning.points = PointCloud();
  r.tuning.sample.clear();
  r.fine_tune_s = Since(t0);
  after(RftaPart::kFineTune);

  // 4. The final surface from the tuned points.
  t0 = Clock::now();
  if (parts.reconstruct) {
    r.surface = parts.reconstruct(r.points);
  } else {
    RftaOptions final_options = options;
    if (dim == 3 && options.carve && final_options.poisson.backend == PoissonOptions::Backend::kArcs)
      final_options.poisson.carve = OutsideSpheresCarve(samples, CarveMargin(samples, options.fine_tune.search.tol,
                                                                             options.carve_margin));
    r.surface = DefaultRftaReconstructor(dim, final_options, /*tuning=*/false, ctx)(r.points);
  }
  if (dim == 2) {
    if (!std::holds_alternative<Polyline>(r.surface))
      throw Error("rfta: the reconstructor gave a mesh for 2D samples (2D samples need a 2D reconstructor, "
                  "e.g. screened_poisson_2d)");
    if (std::get<Polyline>(r.surface).Empty()) throw Error("rfta: the final 2D reconstruction is empty");
  } else if (!std::holds_alternative<Mesh>(r.surface)) {
    throw Error("rfta: the reconstructor gave a 2D curve for 3D samples");
  } else if (options.drop_infeasible_components) {
    const double tol = options.fine_tune.search.tol * ComputeUnitFrame(samples).scale;
    r.components = DropInfeasibleComponents(&std::get<Mesh>(r.surface), samples, tol);
    if (r.components.dropped > 0)
      ctx.Info("rfta: dropped " + std::to_string(r.components.dropped) + " of " +
               std::to_string(r.components.components) +
               " components lying mostly inside the samples' spheres");
    if (r.components.kept_by_fit > 0)
      ctx.Info("rfta: kept " + std::to_string(r.components.kept_by_fit) +
               " components lying mostly inside the samples' spheres: removing them worsened the samples' fit");
  }
  if (dim == 3 && options.small_components > 0) {
    const double limit = options.small_components * SampleSpacing(samples);  // extent, and misfit budget's root
    r.small = DropSmallComponents(&std::get<Mesh>(r.surface), samples, limit, limit * limit);
    if (r.small.dropped > 0)
      ctx.Info("rfta: dropped " + std::to_string(r.small.dropped) + " of " + std::to_string(r.small.candidates) +
               " components smaller than " + std::to_string(options.small_components) +
               " x the samples' spacing (their fit did not need them)");
  }
  r.final_s = Since(t0);
  after(RftaPart::kFinal);
  return r;
}

RftaResult ReachForTheArcs(const SdfSamples& samples, const RftaOptions& options, const Context& ctx) {
  return ReachForTheArcs(samples, options, RftaParts{}, ctx);
}

}  // namespace arcs
