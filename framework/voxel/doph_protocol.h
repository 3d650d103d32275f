// The evaluation protocol of the differentiable-voxelization paper (Luo et
// al., sec. 3.1): occupancy -> marching cubes at 0.5 -> trimesh-style
// Laplacian smoothing -> Chamfer / Hausdorff over 20 000 surface samples,
// repeated 3 times (mean and std).
#pragma once

#include "framework/types.h"

#include <cstdint>

namespace arcs {

// Marching cubes of an occupancy (or winding-number) volume at `level`:
// inside = value > level (the opposite of the SDF convention), triangles
// oriented outward.
Mesh VolumeToMesh(const VolumeGrid& volume, double level = 0.5);

// trimesh.smoothing.filter_laplacian with its defaults except lambda
// (the paper: 10 iterations, lambda 0.15): equal-weight umbrella operator
// over edge neighbours, explicit steps V += lambda (L V - V), and with
// volume_constraint each step rescales about the origin by (V0 / V)^(1/3)
// (skipped when the ratio is not finite and positive, e.g. an open mesh of
// zero volume). Isolated vertices stay put.
struct LaplacianSmoothOptions {
  int iterations = 10;
  double lambda = 0.15;
  bool volume_constraint = true;
  void Check() const;
};
Mesh LaplacianSmooth(const Mesh& mesh, const LaplacianSmoothOptions& options = {});

// Signed volume (divergence theorem; positive for outward closed meshes).
double SignedVolume(const Mesh& mesh);

// The paper's metrics between `output` and `reference`, `samples`
// area-uniform samples on each, nearest-sample distances d1 (output ->
// reference samples) and d2; `repeats` independent draws (seeds derived from
// `seed`), mean and sample std over them.
//   chamfer    = mean(d1) + mean(d2)       (the magnitude of the paper's tables)
//   chamfer_sq = mean(d1^2) + mean(d2^2)   (squared variant, for reference)
//   hausdorff  = max(max d1, max d2)
struct DophMetrics {
  double chamfer = 0, chamfer_std = 0, chamfer_sq = 0, chamfer_sq_std = 0, hausdorff = 0, hausdorff_std = 0;
};
DophMetrics ComputeDophMetrics(const Mesh& output, const Mesh& reference, std::int64_t samples, int repeats,
                               std::uint64_t seed);

}  // namespace arcs
