// Evaluation metrics, each its own named stage (role evaluator). They compare
// the method's output mesh with the reference mesh and/or the SDF samples.
#include "framework/eval/metrics.h"
#include "framework/spatial/topology.h"
#include "stages/builtin.h"

namespace arcs {

namespace {
void Add(Registry& r, const std::string& name, const std::string& doc, ParamSchema params,
         std::vector<std::string> outputs, StageFn fn) {
  RegisterFunctionStage(r, name, Role::kEvaluator, doc, std::move(params), std::move(outputs), std::move(fn));
}
}  // namespace

void RegisterEvalStages(Registry& r) {
  Add(r, "chamfer",
      "the paper's Chamfer: sqrt(mean d1^2) + sqrt(mean d2^2), nearest-sample distances between area-uniform samples",
      ParamSchema().Int("samples", 1000000, "area-uniform samples per mesh (paper: 10^6)", 1, 100000000),
      {"chamfer"}, [](Context& ctx, CaseData& d, const ParamMap& p) {
        d.SetMetric("chamfer", ChamferPaper(d.RequireOutput("chamfer"), d.RequireReference("chamfer"),
                                            p.GetInt("samples"), ctx.StreamSeed("chamfer")));
      });
  Add(r, "hausdorff",
      "the paper's Hausdorff: max over the vertices of each mesh of the distance to the other surface (a lower bound)",
      ParamSchema(), {"hausdorff"}, [](Context&, CaseData& d, const ParamMap&) {
        d.SetMetric("hausdorff", HausdorffPaper(d.RequireOutput("hausdorff"), d.RequireReference("hausdorff")));
      });
  Add(r, "e_sdf", "the paper's SDF energy: 1000 * mean_i (|s_i| - dist(p_i, output))^2 over the input samples",
      ParamSchema(), {"e_sdf"}, [](Context&, CaseData& d, const ParamMap&) {
        d.SetMetric("e_sdf", EnergySdf(d.RequireSamples("e_sdf"), d.RequireOutput("e_sdf")));
      });
  Add(r, "chamfer_p2s",
      "point-to-surface Chamfer: samples of each mesh to the other *surface*, sqrt(mean d1^2) + sqrt(mean d2^2)",
      ParamSchema().Int("samples", 1000000, "area-uniform samples per mesh", 1, 100000000), {"chamfer_p2s"},
      [](Context& ctx, CaseData& d, const ParamMap& p) {
        d.SetMetric("chamfer_p2s",
                    ChamferPointToSurface(d.RequireOutput("chamfer_p2s"), d.RequireReference("chamfer_p2s"),
                                          p.GetInt("samples"), ctx.StreamSeed("chamfer_p2s")));
      });
  Add(r, "hausdorff_sampled",
      "two-sided sampled Hausdorff: max over surface samples and vertices of both meshes to the other surface",
      ParamSchema().Int("samples", 1000000, "area-uniform samples per mesh", 1, 100000000), {"hausdorff_sampled"},
      [](Context& ctx, CaseData& d, const ParamMap& p) {
        d.SetMetric("hausdorff_sampled",
                    HausdorffSampled(d.RequireOutput("hausdorff_sampled"), d.RequireReference("hausdorff_sampled"),
                                     p.GetInt("samples"), ctx.StreamSeed("hausdorff_sampled")));
      });
  Add(r, "topology", "output topology: closed, manifold, oriented, genus (-1 if undefined), components",
      ParamSchema(), {"out_closed", "out_manifold", "out_oriented", "out_genus", "out_components"},
      [](Context&, CaseData& d, const ParamMap&) {
        const Topology t = ComputeTopology(d.RequireOutput("topology"));
        d.SetMetric("out_closed", t.closed);
        d.SetMetric("out_manifold", t.manifold);
        d.SetMetric("out_oriented", t.oriented);
        d.SetMetric("out_genus", t.genus);
        d.SetMetric("out_components", t.components);
      });
  Add(r, "mesh_size", "output vertex and face counts", ParamSchema(), {"out_vertices", "out_faces"},
      [](Context&, CaseData& d, const ParamMap&) {
        const Mesh& m = d.RequireOutput("mesh_size");
        d.SetMetric("out_vertices", m.NumVertices());
        d.SetMetric("out_faces", m.NumFaces());
      });
}

}  // namespace arcs
