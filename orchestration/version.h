#pragma once

namespace arcs {

// The git revision of the code this build compiled, "-dirty" when tracked
// files differed from it (the build's stamp; else the revision at configure
// time; "unknown" outside git).
const char* GitRevision();
// CMAKE_BUILD_TYPE of this build.
const char* BuildType();
// Absolute path of the source tree this binary was built from.
const char* SourceDir();

}  // namespace arcs
