// morph stages (placeholder until the stages land).
#include "stages/builtin.h"

namespace arcs {

void RegisterMorphStages(Registry& r) { (void)r; }

}  // namespace arcs
