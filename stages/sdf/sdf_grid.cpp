// sdf_grid: the paper's SDF sampling protocol (§5): (n+1)^d nodes of
// linspace(lo, hi, n+1)^d, exact unsigned distance, sign from the winding number.
#include "framework/sdf/sdf_sampling.h"
#include "registry/bind.h"
#include "stages/builtin.h"
#include "stages/sdf/sdf_sign_report.h"

namespace arcs {

namespace {

Binder<SdfGridOptions> SdfGridParams() {
  using O = SdfGridOptions;
  return Binder<O>()
      .Int("n", &O::n, "grid cells per axis (the paper's 'grid' n: 6, 10, 20, ..., 100)", Closed(1, SdfGridOptions::kMaxN))
      .Double("lo", &O::lo, "lower grid bound on every axis (paper: -1)")
      .Double("hi", &O::hi, "upper grid bound on every axis (paper: 1; greater than lo)")
      .Enum("sign", &O::sign, kSdfSignNames,
            "inside/outside test: hierarchical winding number, or the exact O(#F) sum")
      .Enum("inside", &O::inside, kSdfInsideNames,
            "inside rule: the voxelizer's orientation-independent |w| > 1/2 with the open-mesh shell "
            "(same nodes as `voxelize`), or the paper's w > 1/2 as the mesh is oriented");
}

void RunSdfGrid(Context& ctx, CaseData& d, const SdfGridOptions& o, const ParamMap&) {
  SdfSignReport rep;
  d.samples = SampleSdfGrid(*d.reference, o, ctx, &rep);
  ReportSdfSign(rep, d);
}

}  // namespace

void RegisterSdfGrid(Registry& r) {
  StageInfo s = DeclareStage(
      "sdf_grid", Role::kSdfSampler,
      "SDF at the (n+1)^3 nodes of linspace(lo,hi,n+1)^3: exact distance, sign by the voxelizer's winding-number "
      "rule (paper §5; orientation-independent, docs/robustness.md)",
      {Slot::kReference}, {Slot::kSamples}, k3D);
  s.outputs = {"sdf_unbalanced_edges", "sdf_shell_samples", "sdf_inward", "sdf_inside_samples"};
  BindStage<SdfGridOptions>(s, SdfGridParams(), RunSdfGrid);
  r.Register(std::move(s));
}

}  // namespace arcs
