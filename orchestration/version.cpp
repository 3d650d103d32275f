// Build provenance baked in at configure time.
#include "orchestration/version.h"

namespace arcs {

const char* GitRevision() { return ARCS_GIT_REV; }
const char* BuildType() { return ARCS_BUILD_TYPE; }
const char* SourceDir() { return ARCS_SOURCE_DIR; }

}  // namespace arcs
