// sdf_grid: the paper's SDF sampling protocol (§5): (n+1)^d nodes of
// linspace(lo, hi, n+1)^d, exact unsigned distance, sign from the winding number.
#include "framework/sdf/sdf_sampling.h"
#include "stages/builtin.h"
#include "stages/sdf/sdf_sign_report.h"

namespace arcs {

void RegisterSdfGrid(Registry& r) {
  StageInfo s;
  s.name = "sdf_grid";
  s.role = Role::kSdfSampler;
  s.doc = "SDF at the (n+1)^3 nodes of linspace(lo,hi,n+1)^3: exact distance, sign by the voxelizer's winding-number "
          "rule (paper §5; orientation-independent, docs/robustness.md)";
  s.params.Int("n", 20, "grid cells per axis (the paper's 'grid' n: 6, 10, 20, ..., 100)", 1, 2048)
      .Double("lo", -1.0, "lower grid bound on every axis (paper: -1)")
      .Double("hi", 1.0, "upper grid bound on every axis (paper: 1)")
      .Choice("sign", "fast_winding_number", {"fast_winding_number", "exact_winding_number"},
              "inside/outside test: hierarchical winding number, or the exact O(#F) sum")
      .Choice("inside", "voxelizer", {"voxelizer", "winding"},
              "inside rule: the voxelizer's orientation-independent |w| > 1/2 with the open-mesh shell "
              "(same nodes as `voxelize`), or the paper's w > 1/2 as the mesh is oriented");
  s.outputs = {"sdf_unbalanced_edges", "sdf_shell_samples", "sdf_inward", "sdf_inside_samples"};
  s.factory = FunctionStage([](Context& ctx, CaseData& d, const ParamMap& p) {
    SdfGridOptions o;
    o.n = static_cast<int>(p.GetInt("n"));
    o.lo = p.GetDouble("lo");
    o.hi = p.GetDouble("hi");
    o.sign = p.GetString("sign") == "exact_winding_number" ? SdfGridOptions::Sign::kExactWindingNumber
                                                           : SdfGridOptions::Sign::kFastWindingNumber;
    o.inside = p.GetString("inside") == "winding" ? SdfInside::kWinding : SdfInside::kVoxelizer;
    if (!(o.hi > o.lo)) throw OptionError("sdf_grid: hi must be greater than lo");
    SdfSignReport rep;
    d.samples = SampleSdfGrid(d.RequireReference("sdf_grid"), o, ctx, &rep);
    ReportSdfSign(rep, d);
  });
  r.Register(std::move(s));
}

}  // namespace arcs
