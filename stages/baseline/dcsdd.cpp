// dcsdd: dual contouring of signed distance data (Carrera et al. 2026), from
// ../shared/notes/baselines.md; deterministic (the batch's random top-up is
// drawn from the case's seed).
#include "framework/sdfmesh/dcsdd.h"
#include "stages/builtin.h"

namespace arcs {

void RegisterDcsdd(Registry& r) {
  StageInfo s;
  s.name = "dcsdd";
  s.role = Role::kSdfToMesh;
  s.doc = "dual contouring of signed distance data (Carrera et al. 2026): DC, then iterated per-cell least squares "
          "that make the surface touch the sample spheres, and Hermite data blended towards the new surface";
  const DcsddOptions def;
  s.params.Int("iterations", def.iterations, "outer iterations (the source: 100)", 0, 100000)
      .Int("batch_size", def.batch_size, "samples per outer iteration: the near-surface ones, topped up at random (the source: 200 000)",
           1, 1000000000)
      .Double("band", def.band, "near-surface band |s| < band cell diagonals (the source: 3)", 0.0, 1e6)
      .Double("drop_distance", def.drop_distance,
              "a sample farther than its radius plus this many cell diagonals from the mesh is dropped (the source: 1)",
              1e-9, 1e6)
      .Double("dc_weight", def.dc_weight, "weight of the Hermite-plane rows in the cell solve (the source: 0.02)", 0.0, 1e6)
      .Double("proximal_weight", def.proximal_weight,
              "proximal term weight w |x - x_prev|^2 (the source: sqrt(0.1) as a row weight)", 1e-12, 1e6)
      .Double("svd_threshold", def.svd_threshold, "truncated SVD of the cell solve, relative (the source: 0.01)", 0.0,
              0.999999)
      .Int("inner_iterations", def.inner_iterations, "Gauss-Newton steps per cell per outer iteration, at most (the source: 100)",
           1, 100000)
      .Double("inner_tolerance", def.inner_tolerance, "a cell stops when its step is below this many cell diagonals", 0.0, 1.0)
      .Double("tolerance", def.tolerance,
              "stop when no vertex moved more than this many cell diagonals in an outer iteration (ours; 0 = run all)",
              0.0, 1.0)
      .Double("blend", def.blend, "Hermite points and normals move this fraction towards the fitted planes (the source: 0.2)",
              0.0, 1.0)
      .Double("dc_svd_threshold", def.dc_svd_threshold, "QEF threshold of the initial dual contouring", 0.0, 0.999999)
      .Bool("clamp_to_cell", def.clamp_to_cell, "keep every vertex inside its grid cell")
      .Bool("manifold", def.manifold, "start from manifold dual contouring (one vertex per marching-cubes sheet)");
  s.outputs = {"dcsdd_sphere_residual", "dcsdd_initial_residual", "dcsdd_iterations", "dcsdd_inner_iterations"};
  s.factory = FunctionStage([](Context& ctx, CaseData& d, const ParamMap& p) {
    const SdfSamples& sm = d.RequireSamples("dcsdd");
    DcsddOptions o;
    o.iterations = static_cast<int>(p.GetInt("iterations"));
    o.batch_size = p.GetInt("batch_size");
    o.band = p.GetDouble("band");
    o.drop_distance = p.GetDouble("drop_distance");
    o.dc_weight = p.GetDouble("dc_weight");
    o.proximal_weight = p.GetDouble("proximal_weight");
    o.svd_threshold = p.GetDouble("svd_threshold");
    o.inner_iterations = static_cast<int>(p.GetInt("inner_iterations"));
    o.inner_tolerance = p.GetDouble("inner_tolerance");
    o.tolerance = p.GetDouble("tolerance");
    o.blend = p.GetDouble("blend");
    o.dc_svd_threshold = p.GetDouble("dc_svd_threshold");
    o.clamp_to_cell = p.GetBool("clamp_to_cell");
    o.manifold = p.GetBool("manifold");
    o.seed = ctx.StreamSeed("dcsdd");
    DcsddStats st;
    d.output = Dcsdd(sm, o, ctx, &st);
    d.SetMetric("dcsdd_sphere_residual", st.mean_sphere_residual);
    d.SetMetric("dcsdd_initial_residual", st.initial_sphere_residual);
    d.SetMetric("dcsdd_iterations", st.iterations);
    d.SetMetric("dcsdd_inner_iterations", st.mean_inner_iterations);
  });
  r.Register(std::move(s));
}

}  // namespace arcs
