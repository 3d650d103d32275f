// Signed-distance samples of a triangle mesh, as the RFTA paper's protocol
// takes them: exact unsigned distance to the surface (closest point on the
// triangles), sign from the generalized winding number w: s = sign(1 - 2w)·d,
// negative inside.
//
// The inside is decided by default by the voxelizer's orientation-independent
// rule (`SdfInside::kVoxelizer`, docs/voxelization.md and docs/robustness.md):
// |w| > 1/2, exact by flood fill on a grid of a closed mesh, and for a mesh
// that is not closed or not consistently oriented (unbalanced edges) the thin
// shell of its "sheet" faces. An inward or misoriented mesh then gets the same
// inside as `arcs voxelize` finds, instead of an all-positive SDF. For a
// closed outward mesh it is the paper's w > 1/2. `kWinding` is the paper's
// plain w > 1/2 (as the file is oriented).
#pragma once

#include "framework/context.h"
#include "framework/types.h"
#include "framework/util/enum_names.h"

#include <cstdint>
#include <string>
#include <vector>

namespace arcs {

// How the inside/outside sign is decided.
enum class SdfSign {
  kFastWindingNumber,   // hierarchical winding number (libigl's fast_winding_number in the paper)
  kExactWindingNumber,  // sum over all triangles, O(#F) per point
};
inline constexpr EnumName<SdfSign> kSdfSignNames[] = {{SdfSign::kFastWindingNumber, "fast_winding_number"},
                                                      {SdfSign::kExactWindingNumber, "exact_winding_number"}};

// Signed distances of `points` to `mesh`: |s| = exact distance to the
// triangles, s < 0 iff the winding number w > 1/2. (numpy's sign(1 - 2w)
// would give s = 0 when w is exactly 1/2; we give +d there, a measure-zero
// difference.) `fwn_beta` is the fast winding number's far-field ratio.
// Throws arcs::Error if the mesh is empty.
VectorXd SignedDistance(const Mesh& mesh, const MatrixX3d& points,
                        SdfSign sign = SdfSign::kFastWindingNumber, double fwn_beta = 2.0);

// Which points are inside (negative).
enum class SdfInside {
  kVoxelizer,  // the voxelizer's rule (orientation-independent, open-mesh shell); default
  kWinding,    // w > 1/2 with the mesh as oriented (the paper's sign(1 - 2w))
};
inline constexpr EnumName<SdfInside> kSdfInsideNames[] = {{SdfInside::kVoxelizer, "voxelizer"},
                                                          {SdfInside::kWinding, "winding"}};

// How the sign of one sampling was decided, for the per-case report.
struct SdfSignReport {
  std::string rule;                  // "voxelizer:flood_fill", "voxelizer:hierarchy", "winding", ...
  std::int64_t unbalanced_edges = 0; // > 0: not closed or not consistently oriented
  std::int64_t shell_samples = 0;    // samples inside only by the open-mesh shell
  double signed_volume = 0.0;        // < 0: the mesh faces inward
  std::int64_t inside = 0;           // samples with s < 0
  std::vector<std::string> warnings; // one line each: not closed / misoriented / inward / no inside
};

struct SdfGridOptions {
  using Sign = SdfSign;
  static constexpr int kMaxN = 2048;  // the largest n (the stages' and the CLI's bound too)
  int n = 20;          // cells per axis, in [1, kMaxN]: (n+1)^3 nodes of linspace(lo, hi, n+1)^3 (paper: 6..100)
  double lo = -1.0;    // box lower corner on every axis (paper: -1, the shape fills about [-0.5, 0.5])
  double hi = 1.0;     // box upper corner on every axis (paper: 1)
  Sign sign = Sign::kFastWindingNumber;  // sign method (paper: fast winding number)
  double fwn_beta = 2.0;  // fast winding number far-field ratio (libigl's default accuracy 2)
  SdfInside inside = SdfInside::kVoxelizer;  // inside rule (kWinding: the paper's w > 1/2 as oriented)
  void Check() const;
};

// The (n+1)^3 grid nodes with their signed distances, in GridInfo order
// (index = i + (n+1)(j + (n+1)k), x fastest); samples.grid is set.
// With kVoxelizer the sign at every node is Voxelize()'s occupancy of the
// same grid (method fast, or exact for Sign::kExactWindingNumber; open_mesh
// auto, orientation abs), so the two agree node for node. `report` (optional)
// says which rule decided; its warnings also go to ctx.Warn.
SdfSamples SampleSdfGrid(const Mesh& mesh, const SdfGridOptions& options, const Context& ctx,
                         SdfSignReport* report = nullptr);

// `count` points uniform in the box [lo, hi]^3 with their signed distances.
// Point i is drawn from HashSeed(ctx.StreamSeed("sdf_random"), i), so the
// result does not depend on the thread count.
// With kVoxelizer the sign is OccupancyAtPoints() with the node spacing of a
// grid of `count` nodes over the box, (hi - lo) / (cbrt(count) - 1), for the
// open-mesh shell.
SdfSamples SampleSdfRandom(const Mesh& mesh, std::int64_t count, double lo, double hi,
                           const Context& ctx, SdfSign sign = SdfSign::kFastWindingNumber,
                           SdfInside inside = SdfInside::kVoxelizer, SdfSignReport* report = nullptr);

// The settings of SampleSdfRandom as one struct (the sdf_random stage's).
struct SdfRandomOptions {
  std::int64_t count = 10000;  // samples, in [1, 1e9]
  double lo = -1.0;            // box lower corner on every axis (finite)
  double hi = 1.0;             // box upper corner on every axis (finite, > lo)
  SdfSign sign = SdfSign::kFastWindingNumber;
  SdfInside inside = SdfInside::kVoxelizer;
  void Check() const;  // OptionError naming the field
};
SdfSamples SampleSdfRandom(const Mesh& mesh, const SdfRandomOptions& options, const Context& ctx,
                           SdfSignReport* report = nullptr);

// Adds N(0, sigma^2) noise to every value (per-index RNG from HashSeed(seed, i)).
// sigma >= 0; sigma = 0 leaves the values unchanged.
void AddGaussianNoise(SdfSamples* samples, double sigma, std::uint64_t seed);
// AddGaussianNoise's setting; Check(): sigma finite and >= 0 (the sdf_noise stage's default 0.01).
struct SdfNoiseOptions {
  double sigma = 0.01;
  void Check() const;
};

// Clamps the values to [-clamp, clamp] and records samples->clamp = clamp
// (clamp > 0): afterwards |s| = clamp only says "at least clamp away".
void ClampSdf(SdfSamples* samples, double clamp);
// ClampSdf's setting; Check(): clamp finite and > 0 (the sdf_clamp stage's default 0.1).
struct SdfClampOptions {
  double clamp = 0.1;
  void Check() const;
};

}  // namespace arcs
