// Internal: the Open3D back-end of ReconstructPoisson, behind an Open3D-free
// interface (implemented in framework/points/open3d/poisson_open3d.cpp, the
// library that already sees Open3D's headers). Callers use
// framework/reconstruct/poisson.h.
//
// Debian's libopen3d-dev 0.16 embeds Kazhdan's PoissonRecon 12
// (CreateFromPointCloudPoisson): FEM degree 1, Neumann boundary, 1.5 samples
// per node, full depth 5, the screening weight normalised by the estimated
// sample area as in PoissonRecon 16/18 (the official RFTA call) -- but the
// weight itself is hard-coded to 2 (PoissonRecon's command-line default for
// degree 1); the official RFTA passes 10. Open3D exposes depth, scale and the
// thread count only.
#pragma once

#include "framework/types.h"

#include <vector>

namespace arcs::poisson_detail {

// True when compiled against Open3D.
bool Open3dPoissonAvailable();

struct Open3dPoissonResult {
  Mesh mesh;                    // raw output, in the input's coordinates
  double estimated_area = -1;   // PoissonRecon's "estimated area" (unit-cube units), -1 if not captured
  double point_weight_sum = -1; // PoissonRecon's average sample weight (ditto)
};

// Runs Open3D's screened Poisson at `depth` with cube side `scale` x the
// bounding box's largest side. `xyz` / `normals` interleaved (3 per point).
// capture_area: raise Open3D's log level to Debug for the call and read
// PoissonRecon's "Point weight / Estimated Area" line (slower: the solver
// then also computes residuals). Calls are serialised (Open3D's logger and
// PoissonRecon's thread pool are process-wide). Throws Error if Open3D fails
// or without Open3D.
Open3dPoissonResult RunOpen3dPoisson(const std::vector<double>& xyz, const std::vector<double>& normals, int depth,
                                     double scale, int threads, bool capture_area);

}  // namespace arcs::poisson_detail
