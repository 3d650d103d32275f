// The 2D evaluators (paper Fig. 5): Chamfer, Hausdorff and E_SDF on curves,
// and the output curve's topology. Each declares the slots it reads and that
// it works in 2D, so a 2D metric on a 3D output is refused at load.
#include "framework/eval/curve_metrics.h"
#include "framework/geometry/curves.h"
#include "stages/builtin.h"
#include "stages/curve_inputs.h"

namespace arcs {

namespace {

void RunChamfer2D(Context& ctx, CaseData& d, const ParamMap& p) {
  d.SetMetric("chamfer_2d", ChamferCurves(RequireOutputCurve(d, "chamfer_2d"), RequireReferenceCurve(d, "chamfer_2d"),
                                          p.GetInt("samples"), ctx.StreamSeed("chamfer_2d")));
}

void RunHausdorff2D(Context& ctx, CaseData& d, const ParamMap& p) {
  d.SetMetric("hausdorff_2d", HausdorffCurves(RequireOutputCurve(d, "hausdorff_2d"),
                                              RequireReferenceCurve(d, "hausdorff_2d"), p.GetInt("samples"),
                                              ctx.StreamSeed("hausdorff_2d")));
}

void RunEnergySdf2D(Context&, CaseData& d, const ParamMap&) {
  d.SetMetric("e_sdf_2d", EnergySdf2D(*d.samples, RequireOutputCurve(d, "e_sdf_2d")));
}

void RunTopology2D(Context&, CaseData& d, const ParamMap&) {
  const Polyline& c = RequireOutputCurve(d, "topology_2d");
  const CurveTopology t = ComputeCurveTopology(c);
  d.SetMetric("out_curve_components", t.components);
  d.SetMetric("out_curve_closed_components", t.closed_components);
  d.SetMetric("out_curve_open_ends", t.open_ends);
  d.SetMetric("out_curve_branch_vertices", t.branch_vertices);
  d.SetMetric("out_curve_holes", t.holes);
  d.SetMetric("out_curve_edges", c.NumEdges());
}

void Register2D(Registry& r, StageInfo s, ParamSchema params, std::vector<std::string> outputs, StageFn fn) {
  s.params = std::move(params);
  s.outputs = std::move(outputs);
  s.factory = FunctionStage(std::move(fn));
  r.Register(std::move(s));
}

}  // namespace

void RegisterEvalStages2D(Registry& r) {
  const Slots curves{Slot::kOutput, Slot::kReference};
  Register2D(r,
             DeclareStage("chamfer_2d", Role::kEvaluator,
                          "the paper's Chamfer on curves: sqrt(mean d1^2) + sqrt(mean d2^2), nearest-sample distances "
                          "between length-uniform samples",
                          curves, {}, k2D),
             ParamSchema().Int("samples", 100000, "length-uniform samples per curve (sampling floor ~2e-5 at 10^5)", 1,
                               100000000),
             {"chamfer_2d"}, RunChamfer2D);
  Register2D(r,
             DeclareStage("hausdorff_2d", Role::kEvaluator,
                          "two-sided Hausdorff between curves: max over vertices and length-uniform samples of each to "
                          "the other curve",
                          curves, {}, k2D),
             ParamSchema().Int("samples", 100000,
                               "extra length-uniform samples per curve (0 = vertices only, the paper's bound)", 0,
                               100000000),
             {"hausdorff_2d"}, RunHausdorff2D);
  Register2D(r,
             DeclareStage("e_sdf_2d", Role::kEvaluator,
                          "the paper's SDF energy on curves: 1000 * mean_i (|s_i| - dist(p_i, output curve))^2 over the "
                          "2D input samples",
                          {Slot::kSamples, Slot::kOutput}, {}, k2D),
             ParamSchema(), {"e_sdf_2d"}, RunEnergySdf2D);
  Register2D(r,
             DeclareStage("topology_2d", Role::kEvaluator,
                          "output curve structure: components, closed components, open ends, branch vertices, holes "
                          "(clockwise loops)",
                          {Slot::kOutput}, {}, k2D),
             ParamSchema(),
             {"out_curve_components", "out_curve_closed_components", "out_curve_open_ends",
              "out_curve_branch_vertices", "out_curve_holes", "out_curve_edges"},
             RunTopology2D);
}

}  // namespace arcs
