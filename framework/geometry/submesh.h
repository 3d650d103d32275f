// Sub-meshes by face: the faces a mask keeps, with only the vertices they use.
#pragma once

#include "framework/types.h"

#include <vector>

namespace arcs {

// The faces f of `mesh` with keep[f] set (in their order) and the vertices
// they use (in their order); every other vertex is dropped. keep has one
// entry per face.
Mesh KeepFaces(const Mesh& mesh, const std::vector<char>& keep);

}  // namespace arcs
