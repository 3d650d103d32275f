// arcs' own screened Poisson surface reconstruction (Kazhdan & Hoppe 2013),
// written for Reach for the Arcs: the official RFTA calls PoissonRecon with
// FEM degree 1, Neumann boundary, depth 10, 1.5 samples per node and point
// weight 10 (area-normalised), and neither Debian library can be told all of
// that (docs/poisson.md). This one can, and it can be warm-started from the
// previous fine-tuning iteration's solution, which PoissonRecon cannot.
//
// The method, in the unit cube [0,1]^3 that the points' bounding cube
// (side `scale` x the largest bounding-box extent, centred) is mapped onto:
//  * Octree. Levels 0..depth; level d has cells of side h = 2^-d. Levels up
//    to full_depth are complete. Each sample s gets a depth d_s from its
//    density (below): its cell and the 26 around it exist at every level up
//    to ceil(d_s). The tree is then graded: when a cell exists at level d,
//    its parent's 26 neighbours exist at d-1.
//  * Basis. FEM degree 1: a trilinear hat ("tent") at every corner of an
//    existing cell of level d. Functions of all levels together span the
//    indicator χ = Σ_d Σ_i x_i^d B_i^d. Neumann boundary: tents at the cube's
//    faces are cut there (natural boundary condition).
//  * Density and depth. Each sample is splatted with a tent into the grid of
//    the kernel depth k = depth - 2; Dens_s, the splat interpolated at the
//    sample, is ~ (samples per unit area) x h_k^2. The sample's area weight is
//    a_s = h_k^2 / Dens_s, and its depth d_s = k + log4(Dens_s / samples_per_node)
//    clamped to [full_depth, depth]: the level whose cells hold about
//    samples_per_node samples (PoissonRecon's adaptive sample depth).
//  * Vector field. V = -Σ_s a_s N_s K_s, where K_s is the tent of the
//    sample's cell at depth d_s normalised to unit integral (split between
//    floor(d_s) and ceil(d_s) by the fraction), so χ rises by ~1 from outside
//    to inside.
//  * Energy. E(χ) = ∫ |∇χ - V|^2 + α ā 2^d Σ_s χ(p_s)^2 at level d, the sum
//    over the samples whose depth reaches d (ceil(d_s) >= d), with α =
//    point_weight and ā the mean a_s: PoissonRecon's pointWeight times the
//    average sample weight, and the screening scaled with the resolution (the
//    2D reconstructor does the same, docs/planar.md) so its balance with the
//    gradient term is the same at every level.
//  * Solver. Cascadic, coarse to fine (as PoissonRecon): level full_depth is
//    solved completely, then each finer level for its own coefficients with
//    the coarser solution fixed (its gradient and values enter the right-hand
//    side exactly, through the nested tents), by Jacobi-preconditioned
//    conjugate gradients to a relative residual `accuracy` or `iters` steps.
//  * Iso-surface. The iso-value is the a_s-weighted mean of χ at the samples.
//    The surface is extracted at the finest level by marching cubes
//    (framework/geometry's watertight case table), tracked cell to cell from
//    every sample's cell and from the sign changes of the complete level, with
//    χ evaluated exactly (trilinear on the finest grid), one-node islands
//    (a node on the other side from its six neighbours) removed: a closed, manifold,
//    outward-wound mesh unless the surface reaches the cube's boundary.
// Deterministic: every set is sorted, every sum is in a fixed order.
#pragma once

#include "framework/context.h"
#include "framework/types.h"

#include <functional>
#include <memory>
#include <vector>

namespace arcs {

// A carving field c (input frame) for the marching cubes: where c > 0 the
// solid is removed, whatever χ says (SpsrOptions::carve).
struct SpsrCarve {
  // c at the points x (`c` resized by the callee): wherever |c(x[i])| <
  // reach, exactly the value `value` gives there; elsewhere any value on the
  // same side at least reach from 0 (<= -reach, >= reach; infinities too).
  // Called with batches of any size (marching cubes' nodes, reach one cell).
  std::function<void(const std::vector<Vec3>& x, double reach, std::vector<double>& c)> near;
  // c(x) itself: where an edge's two ends disagree on c > 0 and one of them
  // was not within reach (never for a 1-Lipschitz c, up to rounding).
  // Thread-safe.
  std::function<double(const Vec3& x)> value;
  explicit operator bool() const { return static_cast<bool>(near); }
};

struct SpsrOptions {
  int depth = 10;               // finest level (2..12)
  int full_depth = 5;           // levels up to here are complete (clamped to depth)
  double scale = 3.2;           // cube side / largest bounding-box extent (official: 1.1x padding per side)
  double samples_per_node = 1.5;
  double point_weight = 10.0;   // α, PoissonRecon's --pointWeight (area-normalised); 0 = unscreened
  int iters = 40;               // CG steps per level above full_depth (cap)
  double accuracy = 1e-3;       // CG relative residual
  // The complete level full_depth: multigrid-preconditioned CG to this
  // relative residual (at most max(200, iters) steps). PoissonRecon solves
  // its base levels with one V-cycle (baseVCycles 1).
  double base_accuracy = 1e-6;
  // How the levels above full_depth are solved (full_depth itself: always
  // CG with the multigrid preconditioner). kCgJacobi: CG preconditioned by
  // the diagonal. kCgGaussSeidel: CG preconditioned by one symmetric
  // Gauss-Seidel sweep in eight colours (node parity: no two nodes of one
  // colour share a stencil or a sample's cell, so each colour updates in
  // parallel and the bits do not depend on the thread count). kGaussSeidel:
  // `gs_iters` forward Gauss-Seidel sweeps in those colours, PoissonRecon's
  // cascadic relaxation (its `iters`, 8 in the official call), no CG.
  enum class FineSolver { kCgJacobi, kCgGaussSeidel, kGaussSeidel };
  FineSolver fine_solver = FineSolver::kCgJacobi;
  int gs_iters = 8;
  int kernel_depth_offset = 2;  // density kernel at depth - this
  // Where a sample's normal is splatted, given its fractional depth d_s.
  // kSplit: 1 - frac(d_s) at floor(d_s) and frac(d_s) at floor(d_s) + 1
  // (Kazhdan & Hoppe's scheme; PoissonRecon 12). kCeil: all of it at
  // ceil(d_s), which is what PoissonRecon 16.01 / 18.04 do (the official
  // RFTA's call): their splat helper is called for the sample's node with
  // weight frac and for its parent with 1 - frac, but splats into the
  // sample's node both times (docs/poisson.md, session 24).
  enum class NormalSplat { kSplit, kCeil };
  NormalSplat normal_splat = NormalSplat::kSplit;
  // Multiplies the samples' density estimate (tent splats: a planar sheet
  // reads between 1/2 and 1 of its samples per node area, 2/3 on average;
  // PoissonRecon's normalised quadratic kernel reads about 1). 1.5 corrects
  // the average: sample depths 0.29 level deeper, areas 2/3 as large.
  double density_scale = 1.0;
  // The iso-value: the mean of the solution at the samples, weighted by
  // their areas a_s (kArea) or each sample alike (kCount: PoissonRecon
  // weighs each octree-merged sample by its point count).
  enum class IsoWeight { kArea, kCount };
  IsoWeight iso_weight = IsoWeight::kArea;
  // The marching-cubes level: the samples' depth at this quantile, rounded
  // up (1 = the finest level with cells). The solution is the same; a finer
  // level only resolves it more finely, with more triangles.
  double extract_quantile = 0.5;
  // When > 0 (input units): no finer than the coarsest level whose cells
  // are at most this side (the quantile's level when that is coarser). RFTA
  // sets it for its fine-tuning surfaces from the SDF samples' spacing
  // (rfta `tuning_cell`), which need not be resolved as finely as the final one.
  double extract_max_cell = 0;
  // A marching-cubes node on the other side of the iso-value from all six
  // face neighbours (a one-node island: an 8-triangle component) takes their
  // mean instead.
  bool remove_node_islands = true;
  // The screening at level d is scaled by 2^(screen_depth_exponent * d).
  double screen_depth_exponent = 1.0;
  // Which points screen level d. kEach: every sample whose depth reaches d,
  // at its own position. kMerged: the samples sharing a cell of level d as
  // one point at their mean position, weighted by their count (PoissonRecon's
  // interpolation info, accumulated up the tree). The two agree where a cell
  // holds one sample; merged drops the spread of χ inside a cell.
  enum class ScreenSamples { kEach, kMerged };
  ScreenSamples screen_samples = ScreenSamples::kEach;
  // Optional carving field (empty = none). A marching-cubes node the field
  // claims (c > 0) is outside whatever χ says, so the solid is χ's inside
  // minus {c > 0} and the surface there follows c's zero set: on an edge the
  // vertex is where the first of χ - iso and c changes side, each linear
  // along the edge. RFTA's final surface uses it to carve away the sample
  // spheres that certify empty space (rfta `carve`,
  // framework/rfta/sphere_carve.h). Both functions must be deterministic.
  SpsrCarve carve;
  // With `carve`: keep closed components that have no vertex on χ's
  // surface (voids the field alone makes inside χ's solid); default: drop them.
  bool carve_keep_voids = false;
};

// Solution of one call, reusable as the starting guess of the next
// (coefficients matched by octree node). Opaque.
struct SpsrWarmStart;

struct SpsrInfo {
  int depth = 0;               // finest level with cells
  int extract_depth = 0;       // level of the marching cubes
  int islands_removed = 0;     // one-node islands given their neighbours' mean
  long long carved_nodes = 0;  // marching-cubes nodes inside χ's solid that `carve` moved outside
  long long carve_only_components = 0;  // components with no vertex on χ's surface (voids `carve` alone made), dropped
  double iso_value = 0;
  double area = 0;             // Σ a_s, in units of the cube's side squared
  long long unknowns = 0;      // coefficients over all levels
  int cg_iterations = 0;       // summed over levels (Gauss-Seidel: sweeps)
  double final_residual = 0;   // relative residual of the finest level's solve
  bool warm_started = false;
  double solve_s = 0, extract_s = 0;
};

// Oriented points (normals pointing out, any non-zero length) -> mesh in the
// points' frame. `warm` (optional): in, the previous call's solution (null =
// cold start); out, this call's. Throws Error on fewer than 10 points,
// missing/zero/non-finite normals, non-finite points, all points at one
// place, or options out of range.
Mesh ReconstructSpsr(const PointCloud& oriented, const SpsrOptions& options, const Context& ctx,
                     std::shared_ptr<SpsrWarmStart>* warm = nullptr, SpsrInfo* info = nullptr);

}  // namespace arcs
