#include "stages/builtin.h"

namespace arcs {

void RegisterBuiltinStages(Registry& r) {
#define ARCS_BUILTIN_STAGE(fn) fn(r);
#include "stages/builtin_list.h"
#undef ARCS_BUILTIN_STAGE
}

}  // namespace arcs
