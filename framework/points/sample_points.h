// Synthetic point clouds from a mesh, for controlled experiments: area-
// uniform samples with the exact face normals, optionally corrupted by
// Gaussian noise, outliers and duplicate points.
#pragma once

#include "framework/types.h"

#include <cstdint>

namespace arcs {

struct SurfacePointOptions {
  // Surface samples (area-uniform, SampleSurfaceUniform). Range 1..1e8.
  std::int64_t count = 10000;
  // Standard deviation of an isotropic Gaussian displacement of each surface
  // sample, in the mesh's units (a dataset normalised to longest side 1:
  // 0.005 = 0.5 % of the object). Normals stay the face normals. Range [0, 1].
  double noise_sigma = 0.0;
  // Outliers added, as a fraction of `count`: uniform in the bounding box
  // enlarged by 10 % per side, each with a uniformly random unit normal.
  // Range [0, 1].
  double outlier_fraction = 0.0;
  // Duplicates added, as a fraction of `count`: exact copies (position and
  // normal) of uniformly drawn surface samples. Range [0, 1].
  double duplicate_fraction = 0.0;
  void Check() const;  // OptionError naming the field
};

// Rows: the `count` surface samples first, then the outliers, then the
// duplicates (so a test can tell them apart). Normals: unit, outward for a
// mesh wound outward. Deterministic per seed at any thread count. Throws
// Error for a mesh without faces or with zero area.
PointCloud SampleSurfacePoints(const Mesh& mesh, const SurfacePointOptions& options, std::uint64_t seed);

}  // namespace arcs
