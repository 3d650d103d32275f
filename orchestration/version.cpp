// Build provenance: the revision of the code this build compiled (the stamp
// cmake/stamp_revision.cmake writes at every build, read once at start),
// else the revision at configure time; build type and source tree.
#include "orchestration/version.h"

#include <fstream>
#include <string>

namespace arcs {

const char* GitRevision() {
  static const std::string rev = [] {
    std::ifstream in(ARCS_REVISION_STAMP);
    std::string s;
    if (in && std::getline(in, s) && !s.empty()) return s;
    return std::string(ARCS_GIT_REV);
  }();
  return rev.c_str();
}
const char* BuildType() { return ARCS_BUILD_TYPE; }
const char* SourceDir() { return ARCS_SOURCE_DIR; }

}  // namespace arcs
