// Internals of the graph-Voronoi reconstruction shared by its translation
// units (not a public interface).
#pragma once

#include "framework/types.h"

#include <vector>

namespace arcs {

// κNN lists in Morton (Z-curve) positions: row s holds the neighbours of
// input row order[s], as positions (nearest first, itself excluded, -1 pads).
// Graph algorithms on these positions touch nearby memory for nearby points.
// mean_dist (optional) is per position.
std::vector<int> KnnListsMorton(const MatrixX3d& P, int kappa, std::vector<int>* order,
                                std::vector<double>* mean_dist, double* tree_seconds,
                                bool* has_coincident);

}  // namespace arcs
