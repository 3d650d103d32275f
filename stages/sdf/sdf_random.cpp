// sdf_random: SDF at uniformly random points of a box (seeded).
#include "framework/sdf/sdf_sampling.h"
#include "registry/bind.h"
#include "stages/builtin.h"
#include "stages/sdf/sdf_sign_report.h"

namespace arcs {

namespace {

Binder<SdfRandomOptions> SdfRandomParams() {
  using O = SdfRandomOptions;
  return Binder<O>()
      .Int("count", &O::count, "number of samples", Closed(1, 1000000000))
      .Double("lo", &O::lo, "lower box bound on every axis")
      .Double("hi", &O::hi, "upper box bound on every axis (greater than lo)")
      .Enum("inside", &O::inside, kSdfInsideNames,
            "inside rule: the voxelizer's orientation-independent |w| > 1/2 with the open-mesh shell, "
            "or the paper's w > 1/2 as the mesh is oriented");
}

void RunSdfRandom(Context& ctx, CaseData& d, const SdfRandomOptions& o, const ParamMap&) {
  SdfSignReport rep;
  d.samples = SampleSdfRandom(*d.reference, o, ctx, &rep);
  ReportSdfSign(rep, d);
}

}  // namespace

void RegisterSdfRandom(Registry& r) {
  StageInfo s = DeclareStage(
      "sdf_random", Role::kSdfSampler,
      "SDF at uniformly random points of the box [lo,hi]^3 (seeded), sign by the voxelizer's winding-number rule",
      {Slot::kReference}, {Slot::kSamples}, k3D);
  s.outputs = {"sdf_unbalanced_edges", "sdf_shell_samples", "sdf_inward", "sdf_inside_samples"};
  BindStage<SdfRandomOptions>(s, SdfRandomParams(), RunSdfRandom);
  r.Register(std::move(s));
}

}  // namespace arcs
