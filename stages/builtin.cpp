#include "stages/builtin.h"

namespace arcs {

void RegisterBuiltinStages(Registry& r) {
  // SDF samplers and modifiers (mesh -> SDF samples).
  RegisterSdfGrid(r);
  RegisterSdfRandom(r);
  RegisterSdfFile(r);
  RegisterSdfNoise(r);
  RegisterSdfClamp(r);
  RegisterSdfSweep(r);
  // SDF -> mesh baselines.
  RegisterMarchingCubes(r);
  RegisterRfts(r);
  RegisterDualContouring(r);
  RegisterDcsdd(r);
  RegisterVdbMesher(r);
  RegisterPowerDiagram(r);
  // RFTA empty-space samplers and arc projector.
  RegisterRasterize(r);
  RegisterRejection(r);
  RegisterMetropolisHastings(r);
  RegisterArcProjector(r);
  RegisterFineTune(r);
  RegisterRfta(r);
  // Surface reconstructors (oriented points -> mesh).
  RegisterScreenedPoisson(r);
  RegisterGraphVoronoi(r);
  RegisterPointReconstructors(r);
  // Point-cloud inputs.
  RegisterPointInputStages(r);
  // Voxelization and morphing.
  RegisterVoxelStages(r);
  RegisterMorphStages(r);
  // 2D.
  RegisterSdfGrid2D(r);
  RegisterSdfRandom2D(r);
  RegisterMarchingSquares(r);
  RegisterScreenedPoisson2D(r);
  RegisterEvalStages2D(r);
  // Evaluators.
  RegisterEvalStages(r);
}

}  // namespace arcs
