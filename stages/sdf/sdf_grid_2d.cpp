// sdf_grid_2d: the paper's grid protocol in the plane (Fig. 5): the exact 2D
// SDF of the case's reference curve at the (n+1)^2 grid nodes.
#include "framework/sdf/sdf2d.h"
#include "registry/bind.h"
#include "stages/builtin.h"
#include "stages/curve_inputs.h"

namespace arcs {

namespace {

Binder<SdfGrid2DOptions> SdfGrid2DParams() {
  using O = SdfGrid2DOptions;
  return Binder<O>()
      .Int("n", &O::n, "grid cells per axis (Fig. 5 style: 10, 20, 40, ...)", Closed(1, SdfGrid2DOptions::kMaxN))
      .Double("lo", &O::lo, "lower grid bound on both axes (paper: -1)")
      .Double("hi", &O::hi, "upper grid bound on both axes (paper: 1; greater than lo)");
}

void RunSdfGrid2D(Context& ctx, CaseData& d, const SdfGrid2DOptions& o, const ParamMap&) {
  d.samples = SampleSdfGrid2D(RequireReferenceCurve(d, "sdf_grid_2d"), o, ctx);
}

}  // namespace

void RegisterSdfGrid2D(Registry& r) {
  StageInfo s = DeclareStage(
      "sdf_grid_2d", Role::kSdfSampler,
      "2D SDF of the reference curve at the (n+1)^2 nodes of linspace(lo,hi,n+1)^2 (paper protocol in the plane)",
      {Slot::kReference}, {Slot::kSamples}, k2D);
  BindStage<SdfGrid2DOptions>(s, SdfGrid2DParams(), RunSdfGrid2D);
  r.Register(std::move(s));
}

}  // namespace arcs
