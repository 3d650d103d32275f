// Mesh input for the single-stage commands (sdf, eval, voxelize, morph): the
// reader's warnings reach the user, a mesh without faces is an error (not an
// empty result with exit 0), and a normalisation failure names the file.
#pragma once

#include "framework/error.h"
#include "framework/geometry/normalize.h"
#include "framework/io/mesh_io.h"

#include <cstdio>
#include <string>

namespace arcs::cli {

inline Mesh ReadMeshForCommand(const std::string& path) {
  MeshReadReport rep;
  Mesh m = ReadMesh(path, &rep);
  for (const auto& w : rep.warnings) std::fprintf(stderr, "arcs: warning: %s: %s\n", path.c_str(), w.c_str());
  if (m.NumFaces() == 0) {
    std::string why = std::to_string(m.NumVertices()) + " vertices and no triangle faces";
    if (!rep.warnings.empty()) why += " (" + rep.warnings.front() + ")";
    throw InputError(path, 0, why + ": nothing to sample, voxelize or measure");
  }
  return m;
}

// For a mesh used in its own frame (no normalisation): coordinates beyond
// 1e150 would overflow squared distances (inf, then NaN in differences).
inline void CheckCoordinateRange(const Mesh& m, const std::string& path) {
  const double mx = m.V.size() ? m.V.cwiseAbs().maxCoeff() : 0.0;
  if (mx > 1e150) {
    char buf[64];
    std::snprintf(buf, sizeof(buf), "%.6g", mx);
    throw InputError(path, 0, std::string("coordinates up to ") + buf +
                                  " would overflow squared distances (used without normalisation, |x| must stay "
                                  "below 1e150)");
  }
}

inline Similarity NormalizeForCommand(Mesh* m, const NormalizeOptions& o, const std::string& path) {
  try {
    return Normalize(m, o);
  } catch (const InputError&) {
    throw;
  } catch (const Error& e) {
    throw InputError(path, 0, e.what());
  }
}

}  // namespace arcs::cli
