// voxelize stages (placeholder until the stages land).
#include "stages/builtin.h"

namespace arcs {

void RegisterVoxelStages(Registry& r) { (void)r; }

}  // namespace arcs
