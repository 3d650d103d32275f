// Screened Poisson surface reconstruction (Kazhdan & Hoppe 2013) from oriented
// points: the surface reconstructor that Reach for the Arcs runs on its
// tangency point cloud (RFTA §3: "We choose screened Poisson Surface
// Reconstruction (sPSR) [Kazhdan and Hoppe 2013]").
//
// The back-end is PCL's pcl::Poisson (a port of PoissonRecon ~v5: adaptive
// octree, B-spline basis, multigrid, screening by interpolation of the
// points' values). It lives in its own translation unit (poisson_pcl.cpp);
// this header exposes no PCL types. When arcs is built without PCL
// (ARCS_WITH_PCL=OFF), ReconstructPoisson throws arcs::Error.
//
// Differences from the official RFTA call (PoissonRecon 16.01, see
// ../shared/notes/rfta_official_facts.md §2): PCL has no choice of boundary
// condition (no Neumann option), normalises the screening weight by the point
// count rather than the sample density, and maps the points' bounding cube,
// enlarged by `scale`, onto the octree's root (RFTA pads the cloud to fill
// about 1/3.2 of the cube and uses depth 10, i.e. ~320 cells across the
// object; with scale 1.1 the same resolution is depth ~8.2). The official
// geometry is depth 10, scale 3.2, samples_per_node 1.5, open_retries 0;
// `area_normalized` gives point_weight PoissonRecon's meaning, and backend
// kOpen3d runs PoissonRecon 12 itself (degree 1, Neumann, weight fixed at 2).
// Measured comparisons: docs/poisson.md.
#pragma once

#include "framework/context.h"
#include "framework/reconstruct/spsr.h"
#include "framework/types.h"
#include "framework/util/enum_names.h"

#include <memory>

namespace arcs {

struct PoissonOptions {
  // Maximum octree depth; the finest cells are (scale * bbox extent) / 2^depth.
  // 0 = automatic (AutoPoissonDepth), from the point spacing. Explicit: 2..12.
  // Deeper than the spacing supports buys nothing: the octree stops refining
  // where a cell holds fewer than `samples_per_node` points.
  int depth = 0;
  // Added to the automatic depth (after its clamp to [6, 10]; the sum is
  // clamped to [2, 12]): -1 or -2 give a coarser, faster surface, e.g. for
  // RFTA's fine-tuning iterations. Ignored when depth > 0. Range -8..4.
  int depth_offset = 0;
  // Depth up to which the octree is complete (PoissonRecon's "fullDepth";
  // PCL default 5). Clamped to `depth` when larger. Range 0..12.
  int min_depth = 5;
  // Screening weight of the point-value term (PCL default 4). 0 gives the
  // unscreened 2006 method. Range [0, 1e6]. PCL scales this weight
  // differently from PoissonRecon 16/18 (which RFTA calls with 10, multiplied
  // by the sample density), so the numbers are not interchangeable. Measured
  // inside RFTA (paper preset, n = 20, docs/decisions.md): bunny_fixed
  // Chamfer 0.0257 at 10, 0.0206 at 100, 0.0162 at 400, broken surfaces at
  // 1600; torus 0.0023 / 0.0021 at 100 / 400. On exact samples of a
  // sphere/torus (20k points, depth 8) 10 beats 4 by 10-25 %, 0 by ~2x.
  double point_weight = 400.0;
  // Minimum number of samples per octree leaf: the octree stops refining
  // where the points are sparser (RFTA/PoissonRecon 1.5; 1 is ~25 % more
  // accurate on exact samples, 15-20 suits noisy ones). Range [0.5, 100].
  double samples_per_node = 1.5;
  // Ratio of the reconstruction cube's side to the points' bounding-box
  // extent (PoissonRecon default 1.1). Range [1.01, 16].
  double scale = 1.1;
  // Triangulate marching-cubes polygons with more than three corners by
  // adding their barycentre (manifold output) rather than splitting them.
  bool manifold = true;
  // OpenMP threads of PCL's solver and iso-surface extraction. Default 1,
  // the only deterministic setting: with 2 threads PCL returns a slightly
  // different mesh (other vertex count). It was also no faster on the shared
  // 2-core machine, and libgomp's spin-waiting there costs 3x the CPU time
  // unless OMP_WAIT_POLICY=PASSIVE is in the environment when the program
  // starts (libgomp reads it once, at load time). Range 1..256.
  int threads = 1;

  // When the output is not closed (boundary loops PCL's cracks do not
  // explain), solve again with point_weight * retry_weight_factor, up to
  // open_retries times; the first closed result is kept (else the last, with
  // a warning). 0 = never retry. Strong screening can leave sheets reaching
  // the reconstruction cube on noisy points (RFTA on fandisk, n = 40: open
  // at 400, closed at 10); points that bound no volume cost the extra solves.
  int open_retries = 2;
  double retry_weight_factor = 0.25;

  // Which implementation solves: kPcl (pcl::Poisson, PoissonRecon ~v5
  // port: FEM degree 2 only, reflected (Neumann) boundary) or kOpen3d
  // (Open3D 0.16's embedded PoissonRecon 12: FEM degree 1, Neumann, 1.5
  // samples per node, area-normalised weight -- but the weight is fixed at
  // 2 and min_depth, samples_per_node, manifold and point_weight are not
  // settable: point_weight other than 2 is reported and ignored).
  // kArcs: arcs' own screened Poisson (spsr.h): FEM degree 1, Neumann,
  // adaptive sample depth, point_weight always area-normalised (PoissonRecon's
  // meaning), deterministic at any thread count, warm-startable; manifold,
  // threads, open_retries and area_normalized do not apply.
  enum class Backend { kPcl, kOpen3d, kArcs };
  Backend backend = Backend::kPcl;
  // kArcs only: CG steps per octree level (cap) and relative residual, and
  // whether a repeated call for the same case (RFTA's fine-tuning) starts
  // from the previous solution.
  int cg_iters = 40;
  double cg_accuracy = 1e-3;
  // kArcs: relative residual of the complete level's multigrid-preconditioned
  // CG (SpsrOptions::base_accuracy).
  double base_accuracy = 1e-6;
  bool warm_start = true;
  // kArcs: how the levels above the complete one are solved, and the sweeps
  // of kGaussSeidel (SpsrOptions::FineSolver).
  SpsrOptions::FineSolver fine_solver = SpsrOptions::FineSolver::kCgJacobi;
  int gs_iters = 8;
  // kArcs: the marching-cubes level is the samples' octree depth at this
  // quantile, rounded up (1 = the finest level); see spsr.h.
  double extract_quantile = 0.5;
  // kArcs: when > 0, marching cubes no finer than cells of this side (input
  // units); SpsrOptions::extract_max_cell. 0 = the quantile's level.
  double extract_max_cell = 0;
  // kArcs: SpsrOptions::normal_splat and density_scale (spsr.h).
  SpsrOptions::NormalSplat normal_splat = SpsrOptions::NormalSplat::kSplit;
  double density_scale = 1.0;
  SpsrOptions::IsoWeight iso_weight = SpsrOptions::IsoWeight::kArea;
  SpsrOptions::ScreenSamples screen_samples = SpsrOptions::ScreenSamples::kEach;
  // false: point_weight is PCL's own number (PCL divides it by the point
  // count: per-point screening w * 2^d / N). true: it means what
  // PoissonRecon 16/18's --pointWeight means (the official RFTA passes 10):
  // the screening of the paper's energy alpha * Area(P)/N * sum chi(p)^2,
  // i.e. PCL receives point_weight * (estimated sample area in the unit
  // reconstruction cube), EstimatePoissonSampleArea below. The Open3D
  // back-end is always area-normalised.
  bool area_normalized = false;
  // kArcs only: SpsrOptions::carve (empty = none). Other back-ends refuse
  // it. The screened_poisson stage builds it from the case's SDF samples
  // when carve_spheres is set (framework/rfta/sphere_carve.h); the field
  // itself is not read by ReconstructPoisson.
  SpsrCarve carve;
  bool carve_spheres = false;
  double carve_margin = 0.0;  // the stage's: a fraction of the samples' spacing (CarveMargin)
  bool carve_keep_voids = false;  // SpsrOptions::carve_keep_voids

  static constexpr int kMinAutoDepth = 6;
  static constexpr int kMaxAutoDepth = 10;

  // Throws OptionError naming the field and its allowed range.
  void Check() const;
};
// The surface the official Reach for the Arcs makes (its every call, the
// fine-tuning surfaces and the final one; ../shared/notes/rfta_official_facts.md
// §2) with arcs' own solver, in full: FEM degree 1, Neumann, depth 10 in a
// cube 3.2x the cloud, 1.5 samples per node, PoissonRecon's point weight 10
// (area-normalised), 8 Gauss-Seidel sweeps per level above the complete one
// (PoissonRecon's cascadic solver), no open-surface re-solves, and
// PoissonRecon 16/18's sample placement and weights: a normal at ceil(depth)
// (normal_splat ceil), depths from a density read as PoissonRecon's
// normalised kernel reads it (density_scale 1.5) and samples weighted by
// 1.5 x their area (point_weight 15 in our units). RFTA's final surface.
// docs/poisson.md, "Session 32" and "Session 39".
PoissonOptions OfficialRftaPoisson();
// RFTA's fine-tuning surfaces: OfficialRftaPoisson's geometry and solver with
// the normal split between two levels, the tents' own density and weight 10
// (sessions 11-38's calibration for both surfaces). A measured deviation:
// the official call on these surfaces too lowers the errors at low n but
// costs the spot n = 10 case (docs/poisson.md, "Session 39").
PoissonOptions RftaTuningPoisson();

// The screened_poisson stage's `normal_splat` names.
inline constexpr EnumName<SpsrOptions::NormalSplat> kSpsrNormalSplatNames[] = {
    {SpsrOptions::NormalSplat::kSplit, "split"},
    {SpsrOptions::NormalSplat::kCeil, "ceil"}};

// The screened_poisson stage's `iso_weight` names.
inline constexpr EnumName<SpsrOptions::IsoWeight> kSpsrIsoWeightNames[] = {
    {SpsrOptions::IsoWeight::kArea, "area"},
    {SpsrOptions::IsoWeight::kCount, "count"}};
inline constexpr EnumName<SpsrOptions::ScreenSamples> kSpsrScreenSamplesNames[] = {
    {SpsrOptions::ScreenSamples::kEach, "each"},
    {SpsrOptions::ScreenSamples::kMerged, "merged"}};

// The screened_poisson stage's `fine_solver` names.
inline constexpr EnumName<SpsrOptions::FineSolver> kSpsrFineSolverNames[] = {
    {SpsrOptions::FineSolver::kCgJacobi, "cg_jacobi"},
    {SpsrOptions::FineSolver::kCgGaussSeidel, "cg_gauss_seidel"},
    {SpsrOptions::FineSolver::kGaussSeidel, "gauss_seidel"}};

// The screened_poisson stage's `backend` names, in its choice order.
inline constexpr EnumName<PoissonOptions::Backend> kPoissonBackendNames[] = {
    {PoissonOptions::Backend::kPcl, "pcl"},
    {PoissonOptions::Backend::kOpen3d, "open3d"},
    {PoissonOptions::Backend::kArcs, "arcs"}};

// The depth the automatic rule picks for `points` with `options.scale`:
//   depth = round(log2(scale * extent / h)) + 1, clamped to [6, 10],
// where extent is the largest side of the bounding box and h = 2 * (median
// distance to the nearest other point over an evenly strided subsample of at
// most 4096 points); for area-uniform samples h ~ 0.94 sqrt(area / n). So
// the finest cells are about half the point spacing: measured on exact
// sphere/torus samples, one level less loses accuracy and one more only
// costs time (5k points -> 7, 20k -> 8, 100k -> 9). Deterministic. Throws
// Error on the same bad inputs as ReconstructPoisson.
int AutoPoissonDepth(const PointCloud& oriented, const PoissonOptions& options);

// Reconstructs a triangle mesh in the points' own coordinates from points
// `oriented.P` and normals `oriented.N` (any non-zero length; normalised).
//
// Output: for points that enclose a volume, a closed, manifold mesh wound
// outward (positive volume; PCL's winding follows the normals, so a closed
// result from inward normals is flipped). Vertices are merged where PCL
// emits two at one position, faces this collapses are dropped, and the rare
// small cracks of PCL's adaptive marching cubes (boundary loops of <= 12
// edges) are closed with fans. Points that do not enclose a volume (an open
// patch, inconsistent normals, very few points) give an open mesh, reported
// through ctx.Warn; PCL's orientation is kept then. The vertex and face order
// is canonical (sorted), so equal PCL output gives bit-identical meshes.
//
// Throws Error, before PCL sees the data (it crashes or silently drops
// points on some of it), when: there are fewer than 10 points, normals are
// missing, a coordinate or normal is not finite, a normal is zero, or all
// points coincide. Throws Error when PCL produces no surface (e.g. depth 2
// on few points) or throws, and Error("screened Poisson needs PCL: install
// libpcl-dev") when arcs was built without PCL.
//
// Caveats of the back-end: calls are serialised process-wide (PCL's octree
// uses a global node allocator); a call cannot be cancelled midway (ctx's
// stop flag is checked before and after); and PCL's PoissonRecon port
// prints rare diagnostics ("[WARNING] Initial residual too low", "Vertex pair
// not in list") straight to stderr/stdout, which arcs cannot reroute without
// hijacking the process's file descriptors.
// `used_weight` (optional) receives the point weight of the returned mesh.
// `warm` (backend kArcs with warm_start, optional): the previous call's
// solution in, this call's out (see spsr.h); other back-ends ignore it.
Mesh ReconstructPoisson(const PointCloud& oriented, const PoissonOptions& options,
                        const Context& ctx, double* used_weight = nullptr,
                        std::shared_ptr<void>* warm = nullptr);

// True when arcs was built with the PCL back-end.
bool PoissonAvailable();
// True when arcs was built with the Open3D back-end.
bool PoissonOpen3dAvailable();

// The area the oriented samples cover, in units of the reconstruction cube
// (side scale x the bounding box's largest side), as PoissonRecon estimates
// it to normalise the screening weight (its "Estimated Area": the sum of
// per-sample weights, each the inverse of the kernel-smoothed sample density
// at depth - 2). Ours: the points are binned into cells of side h, starting
// at PoissonRecon's kernel cell (cube / 2^(depth-2)) and doubling h until the
// count stops growing (< 10 %: the cells cover the surface), and the area is
// (occupied cells) x h^2. That overestimates a surface's true area like
// PoissonRecon's estimate does (measured on sphere clouds, uniform and
// clustered: PoissonRecon 1.07-1.37x the true area, ours 1.23-1.32x; ours /
// PoissonRecon's 0.92-1.16, poisson_faithful_test). Deterministic.
double EstimatePoissonSampleArea(const PointCloud& oriented, double scale, int depth);

}  // namespace arcs
