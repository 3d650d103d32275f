// Build provenance: the revision of the code this program was built from
// (set at start by the stamp the arcs program and the Python module compile
// in, cmake/stamp_revision.cmake), else the revision at configure time;
// build type and source tree.
#include "orchestration/version.h"

#include <string>

namespace arcs {

namespace {
std::string& Stamped() {
  static std::string rev;
  return rev;
}
}  // namespace

bool SetGitRevision(const char* revision) {
  Stamped() = revision ? revision : "";
  return true;
}
const char* GitRevision() { return Stamped().empty() ? ARCS_GIT_REV : Stamped().c_str(); }
const char* BuildType() { return ARCS_BUILD_TYPE; }
const char* SourceDir() { return ARCS_SOURCE_DIR; }

}  // namespace arcs
