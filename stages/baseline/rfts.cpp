// rfts: Reach for the Spheres (Sellán et al. 2023), the RFTA paper's third
// column, as an SDF -> mesh stage (framework/rfts/rfts.h). Writes the flow's
// iterations, halvings of h, whether it hit a singularity (then the output is
// its last converged mesh, as in the paper's table) and the time of its parts.
#include "framework/rfts/rfts.h"
#include "registry/bind.h"
#include "stages/builtin.h"

namespace arcs {

namespace {

Binder<RftsOptions> RftsParams() {
  using O = RftsOptions;
  return Binder<O>()
      .Int("max_iterations", &O::max_iterations, "flow steps at most (official 3D: 20000)", Closed(0, 100000000))
      .Double("tol", &O::tol, "tangency tolerance |(|s| - d)| < tol, absolute (official 1e-2)", LeftOpen(0, 1.0))
      .Double("h", &O::initial_edge_length, "initial target edge length (official 0.2)", LeftOpen(0, 10.0))
      .Double("min_h", &O::min_edge_length,
              "smallest target edge length; 0 = official clip(2 * mean nearest-sample distance, 0.001, 0.1); "
              ">= h: h is never halved",
              Closed(0.0, 10.0))
      .Bool("line_search", &O::line_search, "step size from the line-search formula (official: on)")
      .Double("min_t", &O::min_step, "smallest step t (official 1e-6)", LeftOpen(0, 1.0))
      .Double("max_t", &O::max_step, "largest step t (official 50)", Closed(1.0, 1e6))
      .Double("dt", &O::fixed_step, "step t when line_search is off (official 10)", LeftOpen(0, 1e6))
      .Int("batch_size", &O::batch_size,
           "random samples per iteration, plus every s <= 0 sample (official 3D: 20000; 0 = all)",
           Closed(0, 1000000000))
      .Int("remesh_iterations", &O::remesh_iterations, "Botsch-Kobbelt rounds per flow step (official 1)",
           Closed(0, 100))
      .Double("split_ratio", &O::split_ratio, "remesher splits edges longer than ratio * h (1.4)", LeftOpen(1.0, 10.0))
      .Double("collapse_ratio", &O::collapse_ratio, "remesher collapses edges shorter than ratio * h (0.7)",
              LeftOpen(0, 1.0))
      .Int("patience", &O::patience, "iterations without improvement of 1e-3 tol before h is halved (official 10)",
           Closed(1, 1000000))
      .Int("max_stall", &O::max_stall, "iterations without improvement at min_h before stopping (official 100)",
           Closed(1, 100000000))
      .Int("initial_subdivisions", &O::initial_subdivisions,
           "start mesh: icosphere subdivisions (official 2: 162 vertices)", Closed(0, 7))
      .Double("initial_radius", &O::initial_radius, "start mesh: icosphere radius about the origin (official 1)",
              LeftOpen(0, 100.0))
      .Double("max_area_ratio", &O::max_area_ratio,
              "divergence guard (ours, not in the source): mesh area above ratio * the sample box's surface "
              "counts as a flow singularity (last converged mesh returned)",
              LeftOpen(0, 1e9));
}

void RunRfts(Context& ctx, CaseData& d, const RftsOptions& o, const ParamMap&) {
  const RftsResult res = ReachForTheSpheres(*d.samples, o, ctx);
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
}

}  // namespace

void RegisterRfts(Registry& r) {
  StageInfo s = DeclareStage(
      "rfts", Role::kSdfToMesh,
      "Reach for the Spheres (Sellan et al. 2023; the RFTA paper's RFTS column): a sphere flows to the SDF "
      "spheres' tangency points with local Botsch-Kobbelt remeshing; genus 0 only (keeps the start's genus); "
      "on a flow singularity returns the last converged mesh. Lengths in the frame where the samples' box is "
      "[-1,1] (the paper's protocol); defaults of gpytoolbox's reach_for_the_spheres (3D); docs/rfts.md",
      {Slot::kSamples}, {Slot::kOutput}, k3D);
  BindStage<RftsOptions>(s, RftsParams(), RunRfts);
  r.Register(std::move(s));
}

}  // namespace arcs
