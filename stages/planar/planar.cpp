// 2D stages (placeholder until the stages land).
#include "stages/builtin.h"

namespace arcs {

void RegisterPlanarStages(Registry& r) { (void)r; }

}  // namespace arcs
