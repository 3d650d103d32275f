// The ray-parity ("contains") baseline: a node is inside when a ray from it
// crosses the mesh an odd number of times (trimesh's `contains`, the paper's
// "Trimesh" column). Implemented with Embree 3 (ray_parity_embree.cpp, built
// with ARCS_WITH_EMBREE): one +z ray per grid column collects every hit
// (repeated rtcIntersect1 from just past the previous hit, robust mode), and
// each node's parity is the number of hits above it. Known weaknesses, kept on
// purpose (they are what the baseline measures): open meshes and
// self-intersections give wrong parities; a ray through an edge or vertex may
// count 0 or 2 hits.
#pragma once

#include "framework/types.h"

namespace arcs {

// True when this build has the Embree back-end.
bool HaveRayParity();
// Occupancy (0 / 1) at the nodes of `grid` (GridInfo order). Throws Error
// when built without Embree.
VectorXd RayParityOccupancy(const Mesh& mesh, const GridInfo& grid);

}  // namespace arcs
