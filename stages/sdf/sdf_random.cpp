// sdf_random: SDF at uniformly random points of a box (seeded).
#include "framework/sdf/sdf_sampling.h"
#include "stages/builtin.h"
#include "stages/sdf/sdf_sign_report.h"

namespace arcs {

void RegisterSdfRandom(Registry& r) {
  StageInfo s;
  s.name = "sdf_random";
  s.role = Role::kSdfSampler;
  s.doc = "SDF at uniformly random points of the box [lo,hi]^3 (seeded), sign by the voxelizer's winding-number rule";
  s.params.Int("count", 10000, "number of samples", 1, 1000000000)
      .Double("lo", -1.0, "lower box bound on every axis")
      .Double("hi", 1.0, "upper box bound on every axis")
      .Choice("inside", "voxelizer", {"voxelizer", "winding"},
              "inside rule: the voxelizer's orientation-independent |w| > 1/2 with the open-mesh shell, "
              "or the paper's w > 1/2 as the mesh is oriented");
  s.outputs = {"sdf_unbalanced_edges", "sdf_shell_samples", "sdf_inward", "sdf_inside_samples"};
  s.factory = FunctionStage([](Context& ctx, CaseData& d, const ParamMap& p) {
    if (!(p.GetDouble("hi") > p.GetDouble("lo"))) throw OptionError("sdf_random: hi must be greater than lo");
    const SdfInside inside = p.GetString("inside") == "winding" ? SdfInside::kWinding : SdfInside::kVoxelizer;
    SdfSignReport rep;
    d.samples = SampleSdfRandom(d.RequireReference("sdf_random"), p.GetInt("count"), p.GetDouble("lo"),
                                p.GetDouble("hi"), ctx, SdfSign::kFastWindingNumber, inside, &rep);
    ReportSdfSign(rep, d);
  });
  r.Register(std::move(s));
}

}  // namespace arcs
