// dcsdd: dual contouring of signed distance data (Carrera et al. 2026), from
// ../shared/notes/baselines.md; deterministic (the batch's random top-up is
// drawn from the case's seed).
#include "framework/sdfmesh/dcsdd.h"
#include "registry/bind.h"
#include "stages/builtin.h"

namespace arcs {

namespace {

Binder<DcsddOptions> DcsddParams() {
  using O = DcsddOptions;
  return Binder<O>()
      .Int("iterations", &O::iterations, "outer iterations (the source: 100)", Closed(0, 100000))
      .Int("batch_size", &O::batch_size,
           "samples per outer iteration: the near-surface ones, topped up at random (the source: 200 000)",
           Closed(1, 1000000000))
      .Double("band", &O::band, "near-surface band |s| < band cell diagonals (the source: 3)", Closed(0.0, 1e6))
      .Double("drop_distance", &O::drop_distance,
              "a sample farther than its radius plus this many cell diagonals from the mesh is dropped (the source: 1)",
              LeftOpen(0.0, 1e6))
      .Double("dc_weight", &O::dc_weight, "weight of the Hermite-plane rows in the cell solve (the source: 0.02)",
              Closed(0.0, 1e6))
      .Double("proximal_weight", &O::proximal_weight,
              "proximal term weight w |x - x_prev|^2 (the source: sqrt(0.1) as a row weight)", LeftOpen(0.0, 1e6))
      .Double("svd_threshold", &O::svd_threshold, "truncated SVD of the cell solve, relative (the source: 0.01)",
              HalfOpen(0.0, 1.0))
      .Int("inner_iterations", &O::inner_iterations,
           "Gauss-Newton steps per cell per outer iteration, at most (the source: 100)", Closed(1, 100000))
      .Double("inner_tolerance", &O::inner_tolerance, "a cell stops when its step is below this many cell diagonals",
              Closed(0.0, 1.0))
      .Double("tolerance", &O::tolerance,
              "stop when no vertex moved more than this many cell diagonals in an outer iteration (ours; 0 = run all)",
              Closed(0.0, 1.0))
      .Double("blend", &O::blend,
              "Hermite points and normals move this fraction towards the fitted planes (the source: 0.2)",
              Closed(0.0, 1.0))
      .Double("dc_svd_threshold", &O::dc_svd_threshold, "QEF threshold of the initial dual contouring",
              HalfOpen(0.0, 1.0))
      .Bool("clamp_to_cell", &O::clamp_to_cell, "keep every vertex inside its grid cell")
      .Bool("manifold", &O::manifold, "start from manifold dual contouring (one vertex per marching-cubes sheet)");
}

void RunDcsdd(Context& ctx, CaseData& d, const DcsddOptions& options, const ParamMap&) {
  DcsddOptions o = options;
  o.seed = ctx.StreamSeed("dcsdd");
  DcsddStats st;
  d.output = Dcsdd(*d.samples, o, ctx, &st);
  d.SetMetric("dcsdd_sphere_residual", st.mean_sphere_residual);
  d.SetMetric("dcsdd_initial_residual", st.initial_sphere_residual);
  d.SetMetric("dcsdd_iterations", st.iterations);
  d.SetMetric("dcsdd_inner_iterations", st.mean_inner_iterations);
}

}  // namespace

void RegisterDcsdd(Registry& r) {
  StageInfo s = DeclareStage(
      "dcsdd", Role::kSdfToMesh,
      "dual contouring of signed distance data (Carrera et al. 2026): DC, then iterated per-cell least squares "
      "that make the surface touch the sample spheres, and Hermite data blended towards the new surface",
      {Slot::kSamples}, {Slot::kOutput}, k3D);
  BindStage<DcsddOptions>(s, DcsddParams(), RunDcsdd);
  s.outputs = {"dcsdd_sphere_residual", "dcsdd_initial_residual", "dcsdd_iterations", "dcsdd_inner_iterations"};
  r.Register(std::move(s));
}

}  // namespace arcs
