// Internal: the PCL back-end of ReconstructPoisson (poisson_pcl.cpp), behind a
// PCL-free interface. Callers use framework/reconstruct/poisson.h instead.
#pragma once

#include "framework/reconstruct/poisson.h"

#include <vector>

namespace arcs::poisson_detail {

// True when compiled against PCL.
bool PclAvailable();

// Runs pcl::Poisson<pcl::PointNormal> on already validated input: `xyz` and
// `normals` hold n points and unit normals (3 floats each, interleaved),
// normalised to a cube of side 1 around the origin. `depth` is the resolved
// (explicit) depth. Returns the raw marching-cubes output in the same
// normalised coordinates; polygons with more than 3 corners are fanned.
// Calls are serialised (PCL's octree uses a process-wide node allocator).
// Throws Error if PCL throws, or without PCL.
Mesh RunPclPoisson(const std::vector<float>& xyz, const std::vector<float>& normals,
                   const PoissonOptions& options, int depth);

}  // namespace arcs::poisson_detail
