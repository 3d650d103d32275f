#include "stages/builtin.h"

namespace arcs {

void RegisterBuiltinStages(Registry& r) {
  // SDF samplers and modifiers (mesh -> SDF samples).
  RegisterSdfGrid(r);
  RegisterSdfRandom(r);
  RegisterSdfFile(r);
  RegisterSdfNoise(r);
  RegisterSdfClamp(r);
  // SDF -> mesh baselines.
  RegisterMarchingCubes(r);
  // Evaluators.
  RegisterEvalStages(r);
}

}  // namespace arcs
