// marching_squares: the 2D MC baseline of the paper's Fig. 5 (2D SDF grid ->
// closed polylines).
#include "framework/geometry/curves.h"
#include "framework/geometry/marching_cubes.h"
#include "stages/builtin.h"

namespace arcs {

void RegisterMarchingSquares(Registry& r) {
  RegisterFunctionStage(r, "marching_squares", Role::kSdfToMesh,
      "marching squares on 2D grid SDF samples (linear interpolation on edges; the 2D MC baseline of Fig. 5)",
      ParamSchema().Double("level", 0.0, "iso-value extracted"), {}, [](Context&, CaseData& d, const ParamMap& p) {
        const SdfSamples& sm = d.RequireSamples("marching_squares");
        if (sm.dim != 2) throw Error("marching_squares needs 2D samples; use marching_cubes for 3D");
        if (!sm.grid) throw Error("marching_squares needs samples on a regular grid (e.g. from sdf_grid_2d), got scattered samples");
        d.output_curve = ToPolyline(MarchingSquares(sm.values, *sm.grid, p.GetDouble("level")));
      });
}

}  // namespace arcs
