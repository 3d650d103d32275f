// Area-uniform random points on a triangle mesh.
#pragma once

#include "framework/types.h"

#include <cstdint>

namespace arcs {

// `count` points distributed uniformly by area over the faces of `mesh`
// (a face is drawn from the cumulative area distribution, then a uniform
// point in it with the square-root barycentric trick). Sample i depends only
// on (seed, i) (arcs::HashSeed), so the result is the same at any thread
// count. `faces`, if given, receives the face index of each sample.
// Throws arcs::Error if the mesh has no faces or zero total area, or count < 0.
MatrixX3d SampleSurfaceUniform(const Mesh& mesh, std::int64_t count, std::uint64_t seed,
                               Eigen::VectorXi* faces = nullptr);

}  // namespace arcs
