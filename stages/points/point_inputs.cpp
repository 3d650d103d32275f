// point inputs stages (placeholder until the stages land).
#include "stages/builtin.h"

namespace arcs {

void RegisterPointInputStages(Registry& r) { (void)r; }

}  // namespace arcs
