// Evaluation metrics, each its own named stage (role evaluator). They compare
// the method's output mesh with the reference mesh and/or the SDF samples,
// and write metric columns only (no CaseData slot).
#include "framework/eval/metrics.h"
#include "framework/spatial/topology.h"
#include "registry/bind.h"
#include "stages/builtin.h"

namespace arcs {

namespace {

constexpr Slots kOutputAndReference = {Slot::kOutput, Slot::kReference};

Binder<SampledMetricOptions> SamplesParams(const std::string& doc) {
  using O = SampledMetricOptions;
  return Binder<O>().Int("samples", &O::samples, doc, Closed(1, 100000000));
}

void RunChamfer(Context& ctx, CaseData& d, const SampledMetricOptions& o, const ParamMap&) {
  d.SetMetric("chamfer", ChamferPaper(*d.output, *d.reference, o.samples, ctx.StreamSeed("chamfer")));
}

void RunHausdorff(Context&, CaseData& d, const ParamMap&) {
  d.SetMetric("hausdorff", HausdorffPaper(*d.output, *d.reference));
}

void RunEnergySdf(Context&, CaseData& d, const ParamMap&) {
  d.SetMetric("e_sdf", EnergySdf(*d.samples, *d.output));
}

void RunChamferP2S(Context& ctx, CaseData& d, const SampledMetricOptions& o, const ParamMap&) {
  d.SetMetric("chamfer_p2s",
              ChamferPointToSurface(*d.output, *d.reference, o.samples, ctx.StreamSeed("chamfer_p2s")));
}

void RunHausdorffSampled(Context& ctx, CaseData& d, const SampledMetricOptions& o, const ParamMap&) {
  d.SetMetric("hausdorff_sampled",
              HausdorffSampled(*d.output, *d.reference, o.samples, ctx.StreamSeed("hausdorff_sampled")));
}

void RunTopology(Context&, CaseData& d, const ParamMap&) {
  const Topology t = ComputeTopology(*d.output);
  d.SetMetric("out_closed", t.closed);
  d.SetMetric("out_manifold", t.manifold);
  d.SetMetric("out_oriented", t.oriented);
  d.SetMetric("out_genus", t.genus);
  d.SetMetric("out_components", t.components);
  // Against the reference, when the case has one (issue 10's topology rates:
  // the mean of these over cases is the fraction with the reference's genus
  // and number of components).
  if (d.reference) {
    const Topology rt = ComputeTopology(*d.reference);
    d.SetMetric("ref_components", rt.components);
    d.SetMetric("genus_matches", t.genus == rt.genus ? 1.0 : 0.0);
    d.SetMetric("components_match", t.components == rt.components ? 1.0 : 0.0);
  }
}

void RunMeshSize(Context&, CaseData& d, const ParamMap&) {
  const Mesh& m = *d.output;
  d.SetMetric("out_vertices", m.NumVertices());
  d.SetMetric("out_faces", m.NumFaces());
}

// An evaluator without parameters.
void Add(Registry& r, const std::string& name, const std::string& doc, Slots reads,
         std::vector<std::string> outputs, StageFn fn) {
  StageInfo s = DeclareStage(name, Role::kEvaluator, doc, reads, {}, k3D);
  s.outputs = std::move(outputs);
  s.factory = FunctionStage(std::move(fn));
  r.Register(std::move(s));
}

// An evaluator with a sample count.
void AddSampled(Registry& r, const std::string& name, const std::string& doc, const std::string& samples_doc,
                BoundStageFn<SampledMetricOptions> fn) {
  StageInfo s = DeclareStage(name, Role::kEvaluator, doc, kOutputAndReference, {}, k3D);
  s.outputs = {name};
  BindStage<SampledMetricOptions>(s, SamplesParams(samples_doc), std::move(fn));
  r.Register(std::move(s));
}

}  // namespace

void RegisterEvalStages(Registry& r) {
  AddSampled(r, "chamfer",
             "the paper's Chamfer: sqrt(mean d1^2) + sqrt(mean d2^2), nearest-sample distances between area-uniform "
             "samples",
             "area-uniform samples per mesh (paper: 10^6)", RunChamfer);
  Add(r, "hausdorff",
      "the paper's Hausdorff: max over the vertices of each mesh of the distance to the other surface (a lower bound)",
      kOutputAndReference, {"hausdorff"}, RunHausdorff);
  Add(r, "e_sdf", "the paper's SDF energy: 1000 * mean_i (|s_i| - dist(p_i, output))^2 over the input samples",
      {Slot::kSamples, Slot::kOutput}, {"e_sdf"}, RunEnergySdf);
  AddSampled(r, "chamfer_p2s",
             "point-to-surface Chamfer: samples of each mesh to the other *surface*, sqrt(mean d1^2) + sqrt(mean d2^2)",
             "area-uniform samples per mesh", RunChamferP2S);
  AddSampled(r, "hausdorff_sampled",
             "two-sided sampled Hausdorff: max over surface samples and vertices of both meshes to the other surface",
             "area-uniform samples per mesh", RunHausdorffSampled);
  Add(r, "topology", "output topology: closed, manifold, oriented, genus (-1 if undefined), components",
      {Slot::kOutput},
      {"out_closed", "out_manifold", "out_oriented", "out_genus", "out_components", "ref_components", "genus_matches",
       "components_match"},
      RunTopology);
  Add(r, "mesh_size", "output vertex and face counts", {Slot::kOutput}, {"out_vertices", "out_faces"}, RunMeshSize);
}

}  // namespace arcs
