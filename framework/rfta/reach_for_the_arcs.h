// Reach for the Arcs (paper Alg. 1) as one library call, for both
// dimensions: SDF samples -> a triangle mesh (dim 3) or closed polylines
// (dim 2, paper Fig. 5). It composes the parts of this module:
//   sign check -> empty-space sampler (free_space.h; paper: rasterize)
//   -> arc projector (arc_projector.h, Alg. 2) -> fine-tuning (fine_tune.h,
//   Alg. 3) -> final reconstruction (paper: screened Poisson).
// Everything that depends on the dimension is chosen here from samples.dim:
// the surface type, the fine-tuner's surface queries (mesh / polyline) and
// the default reconstructors (reconstruct/poisson.h in 3D, our 2D screened
// Poisson reconstruct/poisson2d.h in 2D). Sampler and reconstructors can be
// replaced by callbacks (the `rfta` stage runs registered stages through
// them); with none given, the defaults give the same result as the `rfta`
// stage with its defaults (tested).
#pragma once

#include "framework/context.h"
#include "framework/reconstruct/poisson.h"
#include "framework/rfta/component_filter.h"
#include "framework/reconstruct/poisson2d.h"
#include "framework/rfta/arc_projector.h"
#include "framework/rfta/fine_tune.h"
#include "framework/rfta/free_space.h"
#include "framework/types.h"

#include <cstdint>
#include <functional>
#include <variant>

namespace arcs {

// A reconstructed surface: a triangle mesh (3D) or closed polylines (2D,
// z = 0, counter-clockwise around the inside).
using Surface = std::variant<Mesh, Polyline>;

// Oriented points (input frame) -> the surface of their dimension. An empty
// surface inside fine-tuning ends the iterations early (the last points are
// kept); an empty final 2D surface is an error.
using SurfaceReconstructor = std::function<Surface(const PointCloud& oriented)>;

// SDF samples -> free-space samples of both signs (paper §4.1).
using FreeSpaceSampler = std::function<FreeSpaceSamples(const SdfSamples& samples, const Context& ctx)>;

struct RftaOptions {
  RasterizeOptions raster;         // the default empty-space sampler (paper: rasterize)
  ArcProjectorOptions projector;   // Alg. 2 initial tangency points
  FineTuneOptions fine_tune;       // Alg. 3 (k_max, n_max, b, tau, ...)
  // Positive and negative spheres that overlap (not an SDF; noisy SDFs,
  // Fig. 23, have some): kWarn = warn and go on, but refuse when more than
  // half of the outside spheres conflict; kError = refuse; kIgnore = go on.
  enum class OnSignConflict { kWarn, kError, kIgnore };
  OnSignConflict on_sign_conflict = OnSignConflict::kWarn;
  // 3D: remove components of the final mesh most of whose vertices lie
  // inside a sample's sphere by more than fine_tune.search.tol (the samples
  // rule them out; framework/rfta/component_filter.h). Not in the paper: the
  // official code keeps them. The largest component is always kept.
  bool drop_infeasible_components = true;
  // 3D: remove components of the final mesh below the samples' resolution
  // that their fit does not need (framework/rfta/component_filter.h,
  // DropSmallComponents): those other than the largest smaller than
  // small_components x the samples' spacing h (SampleSpacing), smallest
  // first, while together they add at most (small_components x h)^2 to the
  // samples' summed squared misfit. 0 = keep them (the official code). Not
  // in the paper; docs/decisions.md, "Small components".
  double small_components = 0.5;
  // 3D: carve the balls of the outside samples (s > 0) out of the final
  // surface's solid, less fine_tune.search.tol (framework/rfta/sphere_carve.h):
  // the samples certify those balls empty, and a surface from the tangency
  // points alone can still cut through them (sheets across a hollow,
  // bulges). Applies to the default final reconstructor (options.poisson,
  // backend arcs); the rfta stage sets screened_poisson's carve_spheres.
  // Not in the paper: docs/decisions.md, "Carving".
  bool carve = true;
  // The carving's margin: a ball is carved where it is entered by more than
  // max(tol, carve_margin x the samples' spacing h); shallower cuts (a
  // surface grazing a ball) are left as they are. 0.01: on Fig. 9's
  // fertility (n = 30) the cuts shallower than 0.01 h are what opened a
  // handle through a sliver of the solid and split off a piece; at n = 6 and
  // 10 margin 0.01 keeps about three quarters of margin 0's gain
  // (docs/decisions.md, "Carving").
  double carve_margin = 0.01;
  // The default reconstructors (used where RftaParts leaves one empty).
  // 3D, the final surface: the official call in full (OfficialRftaPoisson:
  // arcs' own screened Poisson, depth 10, cube 3.2x, PoissonRecon's weights
  // and sample placement). Inside fine-tuning: its geometry and solver with
  // sessions 11-38's placement and weight (RftaTuningPoisson; the official
  // code makes every surface with one call: a measured deviation,
  // docs/poisson.md session 39), warm-started from the previous iteration.
  PoissonOptions poisson = OfficialRftaPoisson();
  PoissonOptions tuning_poisson = RftaTuningPoisson();
  // 3D: when > 0, the default tuning surfaces are extracted no finer than
  // cells of tuning_cell x the samples' spacing (SampleSpacing; unless
  // tuning_poisson.extract_max_cell is set): fine-tuning needs closest points
  // and sides, not the final surface's detail. 0 = the final surface's level
  // (the official code: one call for both). docs/rfta_table1.md, session 19.
  double tuning_cell = 0;
  Poisson2DOptions poisson_2d;         // 2D final curve
  // 2D curves inside fine-tuning: the same as the final one (as in 3D, where
  // the official code makes every surface with one call).
  Poisson2DOptions tuning_poisson_2d;
  void Check() const;  // throws OptionError naming the field
};

// The parts of one run that vary by dimension or by stage.
enum class RftaPart { kSignCheck, kSampler, kProjector, kFineTune, kFinal };

struct RftaResult {
  Surface surface;                 // the final surface (input frame): Mesh in 3D, Polyline in 2D
  PointCloud points;               // the final tangency points (input frame, outward normals)
  std::vector<int> sample;         // SDF sample of each point
  FreeSpaceSamples free;           // the sampler's free-space samples (input frame)
  ArcProjectorStats projector;     // the arc projector's counts
  FineTuneResult tuning;           // per-iteration statistics (its points are moved into `points`)
  std::int64_t sign_conflicts = 0;     // positive spheres overlapping a negative one by more than 1e-4
  double sign_conflict_depth = 0;      // the deepest such overlap (input units)
  ComponentFilterStats components;     // the final mesh's components and those dropped
  SmallComponentStats small;           // components below the samples' resolution, and those dropped
  // Wall time of each part (seconds).
  double sampler_s = 0, projector_s = 0, fine_tune_s = 0, final_s = 0;
};

// Replaceable parts; an empty one takes the default.
struct RftaParts {
  FreeSpaceSampler sampler;          // default: RasterizeFreeSpace with options.raster
  SurfaceReconstructor reconstruct;  // final surface; default: options.poisson / poisson_2d
  SurfaceReconstructor tuning;       // inside fine-tuning; default: options.tuning_poisson / tuning_poisson_2d
  // Called after each part with the result so far (kSignCheck: before the
  // conflict policy acts; kProjector: `points` are the initial tangency
  // points; kFinal: `surface` is set), e.g. to record a stage's metrics as
  // they come, so a failing part leaves those of the parts before it.
  std::function<void(RftaPart, const RftaResult&)> after;
};

// The whole of Algorithm 1 on samples of dimension 2 or 3. Throws Error on
// unusable samples (CheckRftaSamples: fewer than 2, non-finite, ...), samples
// of one sign, sign conflicts the policy refuses, a reconstructor giving the
// other dimension's surface or an empty final 2D curve; OptionError on bad
// options.
RftaResult ReachForTheArcs(const SdfSamples& samples, const RftaOptions& options, const RftaParts& parts,
                           const Context& ctx);
// The same with the default sampler and reconstructors.
RftaResult ReachForTheArcs(const SdfSamples& samples, const RftaOptions& options, const Context& ctx);

// The default reconstructors of `options` for samples of dimension `dim`
// (the final one, or the one inside fine-tuning): screened Poisson in 3D
// (automatic depth resolved first, as the `screened_poisson` stage does), our
// 2D screened Poisson in 2D. `ctx` must outlive the returned function.
// The tuning surfaces' cell cap (screened Poisson's extract_max_cell, input
// units) that `tuning_cell` asks for on these samples: tuning_cell x
// SampleSpacing in 3D, 0 when tuning_cell is 0 or the samples are 2D.
double TuningMaxCell(const SdfSamples& samples, double tuning_cell);

SurfaceReconstructor DefaultRftaReconstructor(int dim, const RftaOptions& options, bool tuning, const Context& ctx);

}  // namespace arcs
