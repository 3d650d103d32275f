// Paths in experiment files: ${VAR} expansion, resolution relative to the
// file, and the one glob form datasets' `files:` take.
#pragma once

#include <string>
#include <vector>

namespace arcs {

// "${VAR}" expansion from the environment (ARCS_SHARED_DIR defaults to the
// source tree's ../shared, ARCS_SOURCE_DIR to the source tree) and resolution
// relative to `base_dir`. Throws Error for an unset variable or an unclosed ${.
std::string ResolvePath(const std::string& path, const std::string& base_dir);

// Regular files matching a glob pattern (only the last path component may
// contain wildcards), sorted; a pattern without wildcards gives the file
// itself if it exists.
std::vector<std::string> Glob(const std::string& pattern);

}  // namespace arcs
