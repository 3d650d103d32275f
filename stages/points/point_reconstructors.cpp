// point reconstructors stages (placeholder until the stages land).
#include "stages/builtin.h"

namespace arcs {

void RegisterPointReconstructors(Registry& r) { (void)r; }

}  // namespace arcs
