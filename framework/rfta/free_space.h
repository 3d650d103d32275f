// Empty-space samplers of Reach for the Arcs (paper §4.1, Fig. 10): points of
// the feasibility volume W = B \ union of the (shrunk) balls of one sign,
// from which the arc projector takes the closest point to every sphere.
//
// All three samplers run on one sign's SphereSet in the unit frame (see
// sphere_set.h) and test coverage the same way as the official rasteriser: a
// point x is covered by sphere (c, r) if |x - c|^2 <= shrink * r^2 (shrink =
// 0.95, i.e. an effective radius of 0.975 r). The *FreeSpace wrappers split
// the SDF samples by sign, sample both signs apart (paper §4.1 "Sign
// separation") and return input-frame points tagged with their sign.
#pragma once

#include "framework/context.h"
#include "framework/rfta/sphere_set.h"
#include "framework/types.h"

#include <cstddef>
#include <cstdint>

namespace arcs {

// ---------------------------------------------------------------------------
// Rasterisation narrow band (paper §4.1 and footnote 1; official
// outside_points_from_rasterization_cpu).
//
// A res^d grid of cells on [0,1]^d, restricted to the spheres' bounding box
// +- 1 cell; one point per cell, (i + U(0,1)) / res per axis (jitter drawn
// from a per-cell hash, so nothing per cell is stored); a cell is occupied if
// its point is covered by a sphere. Output: the points of the unoccupied cells
// that have an occupied cell among their 3^d neighbours (a narrow band of two
// cells around the union of the balls; farther cells cannot be the closest
// free point to a sphere).
//
// Unlike the official code (a dense res^d jitter array and a byte grid per
// thread: 2.2 GB at res 448), the grid is classified hierarchically: octree
// nodes of 8^d-cell bricks that lie inside one ball or meet none are settled
// whole by ball-tree queries; only bricks near the union's boundary are tested
// cell by cell (against the few balls that reach them) and stored as bit
// masks. Memory: the ball tree (O(N)), 4 bytes per 8^d-cell brick, 64 bytes
// per boundary brick and the output (e.g. 70 MB at N = 101^3, res 448, most of
// it the tree). The result equals the dense rule exactly (same cells, same
// points; tested against a brute force).
struct RasterizeOptions {
  int resolution = 0;         // cells per axis on [0,1]^d; 0 = the official heuristic 64*ceil(N^(1/d)/16) (paper §4.1)
  int max_resolution = 1024;  // cap of the heuristic (official: 1024)
  double shrink = 0.95;       // occupied if |x - c|^2 <= shrink * r^2 (official CPU raster_shrink; effective radius 0.975 r)
  bool jitter = true;         // one uniformly jittered point per cell (official random_perturbation); false = cell centres
  void Check() const;
};

struct RasterizeStats {
  int resolution = 0;                 // the grid resolution used
  std::int64_t band_points = 0;       // output points
  std::int64_t range_cells = 0;       // cells of the restricted grid (bounding box +- 1 cell)
  std::int64_t surface_bricks = 0;    // 8^d bricks tested cell by cell
  std::int64_t mixed_bricks = 0;      // bricks with both occupied and free cells
  std::size_t memory_bytes = 0;       // peak working memory (tree, brick states, masks, output)
};

// The point of raster cell (i, j, k) (k = 0 in 2D): ((i, j, k) + U) / res
// with U in [0,1)^d from a hash of the full-grid cell index
// i + res (j + res k) and `seed` (three SplitMix64 draws), or the cell centre
// without jitter. Nothing per cell is stored; this is the whole rule.
Vec3 RasterCellPoint(std::uint64_t seed, int resolution, int dim, bool jitter, std::int64_t i, std::int64_t j,
                     std::int64_t k);

// The resolution RasterizeOptions implies for N samples in dimension d.
int RasterResolution(const RasterizeOptions& options, std::int64_t num_samples, int dim);

// The narrow band of one sign's free space at the given grid resolution
// (unit frame, #points x 3; z = 0 in 2D). `seed` drives the jitter.
MatrixX3d RasterizeNarrowBand(const SphereSet& spheres, int resolution, const RasterizeOptions& options,
                              std::uint64_t seed, RasterizeStats* stats = nullptr);

// Both signs of `samples` (stream seeds "rasterize/positive", ".../negative").
// Throws arcs::Error for unusable samples or samples of one sign only.
// stats (optional) receives {positive, negative}.
FreeSpaceSamples RasterizeFreeSpace(const SdfSamples& samples, const RasterizeOptions& options,
                                    const Context& ctx, RasterizeStats stats[2] = nullptr);

// ---------------------------------------------------------------------------
// Rejection sampling (paper Fig. 10's baseline): uniform points in [0,1]^d,
// kept when no sphere of the sign covers them, until `count` are kept.
// Draw t uses HashSeed(seed, t), so the result is independent of threads.
struct RejectionOptions {
  std::int64_t count = 100000;         // free points wanted per sign
  double shrink = 0.95;                // coverage test as the rasteriser's (see above)
  std::int64_t max_draws = 50000000;   // per sign; stops early with fewer points (and logs it)
  void Check() const;
};

// Unit-frame points (fewer than count if max_draws ran out); *draws = draws used.
MatrixX3d RejectionSampleFreeSpace(const SphereSet& spheres, const RejectionOptions& options,
                                   std::uint64_t seed, std::int64_t* draws = nullptr);

FreeSpaceSamples RejectionFreeSpace(const SdfSamples& samples, const RejectionOptions& options,
                                    const Context& ctx);

// ---------------------------------------------------------------------------
// Metropolis–Hastings (paper Fig. 10's "Metropolis-Hastings strategy based on
// the minimum sphere distance"): independent random-walk chains on the free
// space with target density proportional to exp(-d(x) / sigma), d(x) =
// distance to the union of the shrunk balls, so the samples concentrate near
// the union's boundary (where the closest points come from). Proposals are
// Gaussian steps; a proposal outside [0,1]^d or covered by a ball is rejected.
// Chains start from uniform free points; after burn_in steps every accepted
// move is recorded. Chain c draws from Rng(HashSeed(seed, c)): the result is
// independent of threads. Kept simple on purpose: it is the comparison, the
// rasteriser is the method.
struct MetropolisOptions {
  std::int64_t count = 100000;  // free points wanted per sign
  double shrink = 0.95;         // coverage test as the rasteriser's
  double sigma = 0.0;           // target length scale (unit frame); 0 = 1/(4 n), a quarter sample spacing, about one raster cell at the heuristic resolution (n = N^(1/d))
  double step = 0.0;            // proposal standard deviation (unit frame); 0 = sigma
  int chains = 64;              // independent chains
  int burn_in = 200;            // steps per chain before recording
  std::int64_t max_steps = 0;   // steps per chain; 0 = burn_in + 50 * count / chains
  void Check() const;
};

// Unit-frame points (fewer than count if the chains ran out of steps).
// `num_samples` (N, all samples) sets the default sigma.
MatrixX3d MetropolisSampleFreeSpace(const SphereSet& spheres, std::int64_t num_samples,
                                    const MetropolisOptions& options, std::uint64_t seed);

FreeSpaceSamples MetropolisFreeSpace(const SdfSamples& samples, const MetropolisOptions& options,
                                     const Context& ctx);

}  // namespace arcs
