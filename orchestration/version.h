#pragma once

namespace arcs {

// The git revision of the source tree at configure time ("unknown" outside git).
const char* GitRevision();
// CMAKE_BUILD_TYPE of this build.
const char* BuildType();
// Absolute path of the source tree this binary was built from.
const char* SourceDir();

}  // namespace arcs
