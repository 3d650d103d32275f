// sdf_grid_2d: the paper's grid protocol in the plane (Fig. 5): the exact 2D
// SDF of the case's reference curve at the (n+1)^2 grid nodes.
#include "framework/sdf/sdf2d.h"
#include "stages/builtin.h"
#include "stages/curve_inputs.h"

namespace arcs {

void RegisterSdfGrid2D(Registry& r) {
  RegisterFunctionStage(r, "sdf_grid_2d", Role::kSdfSampler,
      "2D SDF of the reference curve at the (n+1)^2 nodes of linspace(lo,hi,n+1)^2 (paper protocol in the plane)",
      ParamSchema()
          .Int("n", 20, "grid cells per axis (Fig. 5 style: 10, 20, 40, ...)", 1, 16384)
          .Double("lo", -1.0, "lower grid bound on both axes (paper: -1)")
          .Double("hi", 1.0, "upper grid bound on both axes (paper: 1)"),
      {}, [](Context& ctx, CaseData& d, const ParamMap& p) {
        SdfGrid2DOptions o;
        o.n = static_cast<int>(p.GetInt("n"));
        o.lo = p.GetDouble("lo");
        o.hi = p.GetDouble("hi");
        d.samples = SampleSdfGrid2D(RequireReferenceCurve(d, "sdf_grid_2d"), o, ctx);
      });
}

}  // namespace arcs
