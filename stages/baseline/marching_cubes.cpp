// marching_cubes: the paper's MC baseline column (SDF grid -> mesh).
#include "framework/geometry/marching_cubes.h"
#include "stages/builtin.h"

namespace arcs {

namespace {

void RunMarchingCubes(Context&, CaseData& d, const ParamMap& p) {
  const SdfSamples& sm = *d.samples;
  if (!sm.grid) throw Error("needs samples on a regular grid (e.g. from sdf_grid), got scattered samples");
  if (sm.dim != 3) throw Error("needs 3D samples; use marching_squares for 2D");
  d.output = MarchingCubes(sm.values, *sm.grid, p.GetDouble("level"));
}

}  // namespace

void RegisterMarchingCubes(Registry& r) {
  StageInfo s = DeclareStage("marching_cubes", Role::kSdfToMesh,
                             "marching cubes on grid SDF samples (linear interpolation on edges; the paper's MC column)",
                             {Slot::kSamples}, {Slot::kOutput}, k3D);
  s.params.Double("level", 0.0, "iso-value extracted");
  s.factory = FunctionStage(RunMarchingCubes);
  r.Register(std::move(s));
}

}  // namespace arcs
