// marching_squares: the 2D MC baseline of the paper's Fig. 5 (2D SDF grid ->
// closed polylines).
#include "framework/geometry/curves.h"
#include "framework/geometry/marching_cubes.h"
#include "stages/builtin.h"

namespace arcs {

namespace {

void RunMarchingSquares(Context&, CaseData& d, const ParamMap& p) {
  const SdfSamples& sm = *d.samples;
  if (!sm.grid) throw Error("needs samples on a regular grid (e.g. from sdf_grid_2d), got scattered samples");
  d.output_curve = ToPolyline(MarchingSquares(sm.values, *sm.grid, p.GetDouble("level")));
}

}  // namespace

void RegisterMarchingSquares(Registry& r) {
  StageInfo s = DeclareStage(
      "marching_squares", Role::kSdfToMesh,
      "marching squares on 2D grid SDF samples (linear interpolation on edges; the 2D MC baseline of Fig. 5)",
      {Slot::kSamples}, {Slot::kOutput}, k2D);
  s.params.Double("level", 0.0, "iso-value extracted");
  s.factory = FunctionStage(RunMarchingSquares);
  r.Register(std::move(s));
}

}  // namespace arcs
