#pragma once

namespace arcs {

// The git revision of the code this program was built from, "-dirty" when
// tracked files differed from it (the build's stamp, in the arcs program and
// the Python module); elsewhere the revision at configure time; "unknown"
// outside git.
const char* GitRevision();
// Called by the stamp compiled into a program (cmake/stamp_revision.cmake).
bool SetGitRevision(const char* revision);
// CMAKE_BUILD_TYPE of this build.
const char* BuildType();
// Absolute path of the source tree this binary was built from.
const char* SourceDir();

}  // namespace arcs
