// marching_cubes: the paper's MC baseline column (SDF grid -> mesh).
#include "framework/geometry/marching_cubes.h"
#include "stages/builtin.h"

namespace arcs {

void RegisterMarchingCubes(Registry& r) {
  StageInfo s;
  s.name = "marching_cubes";
  s.role = Role::kSdfToMesh;
  s.doc = "marching cubes on grid SDF samples (linear interpolation on edges; the paper's MC column)";
  s.params.Double("level", 0.0, "iso-value extracted");
  s.factory = FunctionStage([](Context&, CaseData& d, const ParamMap& p) {
    const SdfSamples& sm = d.RequireSamples("marching_cubes");
    if (!sm.grid) throw Error("marching_cubes needs samples on a regular grid (e.g. from sdf_grid), got scattered samples");
    if (sm.dim != 3) throw Error("marching_cubes needs 3D samples; use marching_squares for 2D");
    d.output = MarchingCubes(sm.values, *sm.grid, p.GetDouble("level"));
  });
  r.Register(std::move(s));
}

}  // namespace arcs
