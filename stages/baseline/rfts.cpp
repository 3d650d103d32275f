// rfts: Reach for the Spheres (Sellán et al. 2023), the RFTA paper's third
// column, as an SDF -> mesh stage (framework/rfts/rfts.h). Writes the flow's
// iterations, halvings of h, whether it hit a singularity (then the output is
// its last converged mesh, as in the paper's table) and the time of its parts.
#include "framework/rfts/rfts.h"
#include "stages/builtin.h"

namespace arcs {

void RegisterRfts(Registry& r) {
  const RftsOptions def;
  StageInfo s;
  s.name = "rfts";
  s.role = Role::kSdfToMesh;
  s.doc = "Reach for the Spheres (Sellan et al. 2023; the RFTA paper's RFTS column): a sphere flows to the SDF "
          "spheres' tangency points with local Botsch-Kobbelt remeshing; genus 0 only (keeps the start's genus); "
          "on a flow singularity returns the last converged mesh. Lengths in the frame where the samples' box is "
          "[-1,1] (the paper's protocol); defaults of gpytoolbox's reach_for_the_spheres (3D); docs/rfts.md";
  s.params.Int("max_iterations", def.max_iterations, "flow steps at most (official 3D: 20000)", 0, 100000000)
      .Double("tol", def.tol, "tangency tolerance |(|s| - d)| < tol, absolute (official 1e-2)", 1e-12, 1.0)
      .Double("h", def.initial_edge_length, "initial target edge length (official 0.2)", 1e-6, 10.0)
      .Double("min_h", def.min_edge_length,
              "smallest target edge length; 0 = official clip(2 * mean nearest-sample distance, 0.001, 0.1)", 0.0,
              10.0)
      .Bool("line_search", def.line_search, "step size from the line-search formula (official: on)")
      .Double("min_t", def.min_step, "smallest step t (official 1e-6)", 1e-12, 1e6)
      .Double("max_t", def.max_step, "largest step t (official 50)", 1e-12, 1e6)
      .Double("dt", def.fixed_step, "step t when line_search is off (official 10)", 1e-12, 1e6)
      .Int("batch_size", def.batch_size,
           "random samples per iteration, plus every s <= 0 sample (official 3D: 20000; 0 = all)", 0, 1000000000)
      .Int("remesh_iterations", def.remesh_iterations, "Botsch-Kobbelt rounds per flow step (official 1)", 0, 100)
      .Double("split_ratio", def.split_ratio, "remesher splits edges longer than ratio * h (1.4)", 1.0 + 1e-9, 10.0)
      .Double("collapse_ratio", def.collapse_ratio, "remesher collapses edges shorter than ratio * h (0.7)", 1e-9,
              10.0)
      .Int("patience", def.patience, "iterations without improvement of 1e-3 tol before h is halved (official 10)",
           1, 1000000)
      .Int("max_stall", def.max_stall, "iterations without improvement at min_h before stopping (official 100)", 1,
           100000000)
      .Int("initial_subdivisions", def.initial_subdivisions,
           "start mesh: icosphere subdivisions (official 2: 162 vertices)", 0, 7)
      .Double("initial_radius", def.initial_radius, "start mesh: icosphere radius about the origin (official 1)",
              1e-9, 100.0)
      .Double("max_area_ratio", def.max_area_ratio,
              "divergence guard (ours, not in the source): mesh area above ratio * the sample box's surface "
              "counts as a flow singularity (last converged mesh returned)",
              1e-9, 1e9);
  s.factory = FunctionStage([](Context& ctx, CaseData& d, const ParamMap& p) {
    const SdfSamples& sm = d.RequireSamples("rfts");
    RftsOptions o;
    o.max_iterations = static_cast<int>(p.GetInt("max_iterations"));
    o.tol = p.GetDouble("tol");
    o.initial_edge_length = p.GetDouble("h");
    o.min_edge_length = p.GetDouble("min_h");
    o.line_search = p.GetBool("line_search");
    o.min_step = p.GetDouble("min_t");
    o.max_step = p.GetDouble("max_t");
    o.fixed_step = p.GetDouble("dt");
    o.batch_size = p.GetInt("batch_size");
    o.remesh_iterations = static_cast<int>(p.GetInt("remesh_iterations"));
    o.split_ratio = p.GetDouble("split_ratio");
    o.collapse_ratio = p.GetDouble("collapse_ratio");
    o.patience = static_cast<int>(p.GetInt("patience"));
    o.max_stall = static_cast<int>(p.GetInt("max_stall"));
    o.initial_subdivisions = static_cast<int>(p.GetInt("initial_subdivisions"));
    o.initial_radius = p.GetDouble("initial_radius");
    o.max_area_ratio = p.GetDouble("max_area_ratio");
    const RftsResult res = ReachForTheSpheres(sm, o, ctx);
    if (res.singular) ctx.Warn("rfts: " + res.stop_reason + "; returning the last converged mesh");
    d.SetMetric("rfts_iterations", res.iterations);
    d.SetMetric("rfts_halvings", res.halvings);
    d.SetMetric("rfts_singular", res.singular ? 1.0 : 0.0);
    d.SetMetric("rfts_converged", res.stop_reason == "converged" ? 1.0 : 0.0);
    d.SetMetric("rfts_min_h", res.min_edge_length);
    d.SetMetric("rfts_final_invalid", static_cast<double>(res.final_invalid));
    d.SetMetric("rfts_query_s", res.query_s);
    d.SetMetric("rfts_solve_s", res.solve_s);
    d.SetMetric("rfts_remesh_s", res.remesh_s);
    d.output = res.mesh;
  });
  r.Register(std::move(s));
}

}  // namespace arcs
