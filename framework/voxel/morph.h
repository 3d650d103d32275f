// Mesh morphing by differentiable voxelization (Luo et al. §2.4): deform a
// source mesh (by default an icosphere) so that its soft occupancy matches a
// target occupancy grid, with a Laplacian smoothness term, optimised with Adam.
//
// Loss (per iteration, on a batch S of grid nodes):
//   E = 1/|S| Σ_{q∈S} ℓ(φ(w(q)), t(q))  +  smooth · 1/|V| Σ_i |v_i - mean_{j~i} v_j|²
// with w the eq. 4 (naive) winding number by default — the paper's choice for
// morphing, since the exact (Alg. 1) winding number of a closed mesh has a
// vanishing gradient — φ = identity (the paper: occupancy = w) and ℓ = squared
// error. The paper does not give its loss, regulariser weights or optimiser
// settings (it defers to its reference [14]); ours are documented defaults,
// tuned on the tests' shapes and on spot (docs/morphing.md).
//
// Speed (the dense sum is O(#nodes · #faces) per iteration): the loss is
// evaluated on an *active set* of nodes, refreshed every `refresh_every`
// iterations from the hard occupancy of the current mesh (fast winding number
// at every node, which also gives the logged IoU): nodes within `band` voxels
// of the target's or the current surface, plus every node whose hard
// occupancy disagrees with the target. Away from both surfaces the residual
// φ(w) - t is ~0 and contributes nothing. Each iteration draws `batch` nodes:
// (1 - random_fraction) from the active set (without replacement) and the rest
// uniformly from the whole grid.
//
// Determinism: one seeded stream (the context's "morph" stream); the
// gradients are deterministic at any thread count (see gradient.h), so a run
// gives the same mesh at 1 and 2 threads.
#pragma once

#include "framework/context.h"
#include "framework/types.h"
#include "framework/util/enum_names.h"
#include "framework/voxel/gradient.h"

#include <functional>
#include <string>
#include <vector>

namespace arcs {


// Hard occupancy (1 inside, 0 outside) of `mesh` at every grid node: fast
// winding number w > 0.5 (agrees with the exact sum near the surface; see
// winding_number.h).
VectorXd HardOccupancy(const Mesh& mesh, const GridInfo& grid);

// Intersection over union of two occupancy vectors (inside iff > 0.5).
// Both empty -> 1.
double OccupancyIoU(const VectorXd& a, const VectorXd& b);

// An icosphere (20·4^subdivisions faces) centred at the centroid of the
// occupied nodes of `target`, with the radius of the sphere of the same volume
// (occupied nodes × cell volume). Throws Error if nothing is occupied.
Mesh InitialSphere(const VolumeGrid& target, int subdivisions);

// Places `source` for morphing: its bounding-box centre on the centre of the
// target's occupied nodes' bounding box, its longest side scaled to that box's
// longest side. Throws Error if nothing is occupied or the source is empty.
Mesh FitSourceToTarget(const Mesh& source, const VolumeGrid& target);

enum class MorphResidual {
  kSoft,   // ℓ on φ(w) of the chosen form (the paper's: the gradient of the stated loss)
  kExact,  // residual from the hard (exact-sign) occupancy, gradient through the form's w:
           // a surrogate ("straight-through") gradient that vanishes once every node agrees
};
const char* MorphResidualName(MorphResidual r);
MorphResidual ParseMorphResidual(const std::string& name);  // "soft" | "exact"
inline constexpr EnumName<MorphResidual> kMorphResidualNames[] = {{MorphResidual::kSoft, "soft"},
                                                                 {MorphResidual::kExact, "exact"}};

struct MorphOptions {
  int iterations = 200;        // Adam steps
  double lr = 0.004;           // Adam learning rate (grid units: the frame of the target grid)
  double beta1 = 0.9;          // Adam moment decays (Kingma & Ba defaults)
  double beta2 = 0.999;
  double smooth = 20.0;        // weight of the uniform-Laplacian energy (0 = none)
  int batch = 4096;            // grid nodes per iteration (0 = the whole active set)
  double random_fraction = 0.1;  // share of the batch drawn uniformly from the whole grid
  int band = 2;                // active band half-width around both surfaces, in voxels
  int refresh_every = 10;      // iterations between active-set refreshes (and IoU logs)
  MorphResidual residual = MorphResidual::kSoft;
  // Softening ε of the naive kernel in grid spacings (sets loss.occupancy.softening;
  // 0 = eq. 4 exactly, which diverged on spot at 64³: see soft_occupancy.h).
  double softening_voxels = 1.0;
  OccupancyLossOptions loss;   // form naive (eq. 4), map identity, loss mse
  void Check() const;          // every field in range; throws OptionError naming it
};

struct MorphLogEntry {
  int iteration = 0;   // number of Adam steps taken so far
  double iou = 0.0;    // hard occupancy of the current mesh vs target, all grid nodes
  double loss = 0.0;   // batch loss of the last step (data + smoothness); 0 before the first
  int active = 0;      // active-set size
  double seconds = 0;  // wall time since the start
};

struct MorphResult {
  Mesh mesh;                      // the morphed mesh (the source's connectivity)
  std::vector<MorphLogEntry> log; // one entry per refresh and the final state
  double initial_iou = 0.0;
  double final_iou = 0.0;
  int iterations = 0;
  double seconds = 0.0;
};

// Morphs `source` (already placed in the grid's frame; see InitialSphere /
// FitSourceToTarget) towards `target` (values > 0.5 = inside). `on_log` is
// called at every log entry. Checks ctx.CheckStop() every iteration. Throws
// Error for an empty source, a target without occupied nodes, or a grid with
// fewer than 2 nodes per axis.
MorphResult MorphToOccupancy(const Mesh& source, const VolumeGrid& target,
                             const MorphOptions& options, Context& ctx,
                             const std::function<void(const MorphLogEntry&)>& on_log = {});

// The uniform-Laplacian energy (1/|V|) Σ_i |v_i - mean_{j~i} v_j|² of `mesh`
// and, when `grad` is not null, its gradient (#V x 3). Isolated vertices
// contribute 0.
double UniformLaplacianEnergy(const Mesh& mesh, MatrixX3d* grad);

}  // namespace arcs
