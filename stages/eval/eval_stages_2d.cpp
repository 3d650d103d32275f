// The 2D evaluators (paper Fig. 5): Chamfer, Hausdorff and E_SDF on curves,
// and the output curve's topology.
#include "framework/eval/curve_metrics.h"
#include "framework/geometry/curves.h"
#include "stages/builtin.h"
#include "stages/curve_inputs.h"

namespace arcs {

void RegisterEvalStages2D(Registry& r) {
  RegisterFunctionStage(r, "chamfer_2d", Role::kEvaluator,
      "the paper's Chamfer on curves: sqrt(mean d1^2) + sqrt(mean d2^2), nearest-sample distances between length-uniform samples",
      ParamSchema().Int("samples", 100000, "length-uniform samples per curve (sampling floor ~2e-5 at 10^5)", 1, 100000000),
      {"chamfer_2d"}, [](Context& ctx, CaseData& d, const ParamMap& p) {
        d.SetMetric("chamfer_2d", ChamferCurves(RequireOutputCurve(d, "chamfer_2d"), RequireReferenceCurve(d, "chamfer_2d"),
                                                p.GetInt("samples"), ctx.StreamSeed("chamfer_2d")));
      });
  RegisterFunctionStage(r, "hausdorff_2d", Role::kEvaluator,
      "two-sided Hausdorff between curves: max over vertices and length-uniform samples of each to the other curve",
      ParamSchema().Int("samples", 100000, "extra length-uniform samples per curve (0 = vertices only, the paper's bound)", 0,
                        100000000),
      {"hausdorff_2d"}, [](Context& ctx, CaseData& d, const ParamMap& p) {
        d.SetMetric("hausdorff_2d", HausdorffCurves(RequireOutputCurve(d, "hausdorff_2d"),
                                                    RequireReferenceCurve(d, "hausdorff_2d"), p.GetInt("samples"),
                                                    ctx.StreamSeed("hausdorff_2d")));
      });
  RegisterFunctionStage(r, "e_sdf_2d", Role::kEvaluator,
      "the paper's SDF energy on curves: 1000 * mean_i (|s_i| - dist(p_i, output curve))^2 over the 2D input samples",
      ParamSchema(), {"e_sdf_2d"}, [](Context&, CaseData& d, const ParamMap&) {
        d.SetMetric("e_sdf_2d", EnergySdf2D(d.RequireSamples("e_sdf_2d"), RequireOutputCurve(d, "e_sdf_2d")));
      });
  RegisterFunctionStage(r, "topology_2d", Role::kEvaluator,
      "output curve structure: components, closed components, open ends, branch vertices, holes (clockwise loops)",
      ParamSchema(),
      {"out_curve_components", "out_curve_closed_components", "out_curve_open_ends", "out_curve_branch_vertices",
       "out_curve_holes", "out_curve_edges"},
      [](Context&, CaseData& d, const ParamMap&) {
        const Polyline& c = RequireOutputCurve(d, "topology_2d");
        const CurveTopology t = ComputeCurveTopology(c);
        d.SetMetric("out_curve_components", t.components);
        d.SetMetric("out_curve_closed_components", t.closed_components);
        d.SetMetric("out_curve_open_ends", t.open_ends);
        d.SetMetric("out_curve_branch_vertices", t.branch_vertices);
        d.SetMetric("out_curve_holes", t.holes);
        d.SetMetric("out_curve_edges", c.NumEdges());
      });
}

}  // namespace arcs
