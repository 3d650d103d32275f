// The 2D stages (paper Fig. 5): 2D SDF sampling of the case's reference
// curve, marching squares, the 2D screened Poisson reconstructor and the 2D
// metrics. 2D Reach for the Arcs is the `rfta` stage on dim-2 samples.
#include "stages/planar/planar.h"

#include "framework/geometry/marching_cubes.h"
#include "framework/planar/curve_metrics.h"
#include "framework/planar/curves.h"
#include "framework/planar/poisson2d.h"
#include "framework/planar/sdf2d.h"
#include "stages/builtin.h"

namespace arcs {

StageSpec PlanarReconstructorFor(const StageSpec& spec, const Registry* registry) {
  if (!registry) throw Error("rfta (2D): needs the case's registry to run its reconstructor");
  if (spec.stage != "screened_poisson") return spec;
  // A coarser 3D preset (depth_offset < 0, RFTA's tuning reconstructor: -3)
  // becomes one power of two coarser per three octree levels.
  ParamMap given;
  if (spec.params.Has("depth_offset")) {
    const std::int64_t d = spec.params.GetInt("depth_offset");
    const std::int64_t shift = d >= 0 ? 0 : -((-d + 2) / 3);
    if (shift != 0) given.Set("resolution_shift", std::max<std::int64_t>(shift, -4));
  }
  return StageSpec{"screened_poisson_2d", registry->Resolve("screened_poisson_2d", given)};
}

namespace {

const Polyline& RequireReferenceCurve(const CaseData& d, const std::string& stage) {
  if (!d.reference_curve)
    throw Error(stage + ": needs a 2D reference curve (a dataset of kind 'curves'); this case has " +
                (d.reference ? "a 3D reference mesh" : "no reference"));
  return *d.reference_curve;
}

const Polyline& RequireOutputCurve(const CaseData& d, const std::string& stage) {
  if (!d.output_curve)
    throw Error(stage + ": needs a 2D output curve (from marching_squares, screened_poisson_2d or rfta on 2D samples)" +
                (d.output ? std::string("; this case's output is a 3D mesh") : std::string()));
  return *d.output_curve;
}

}  // namespace

void RegisterPlanarStages(Registry& r) {
  RegisterFunctionStage(r, "sdf_grid_2d", Role::kSdfSampler,
      "2D SDF of the reference curve at the (n+1)^2 nodes of linspace(lo,hi,n+1)^2 (paper protocol in the plane)",
      ParamSchema()
          .Int("n", 20, "grid cells per axis (Fig. 5 style: 10, 20, 40, ...)", 1, 16384)
          .Double("lo", -1.0, "lower grid bound on both axes (paper: -1)")
          .Double("hi", 1.0, "upper grid bound on both axes (paper: 1)"),
      {}, [](Context& ctx, CaseData& d, const ParamMap& p) {
        SdfGrid2DOptions o;
        o.n = static_cast<int>(p.GetInt("n"));
        o.lo = p.GetDouble("lo");
        o.hi = p.GetDouble("hi");
        d.samples = SampleSdfGrid2D(RequireReferenceCurve(d, "sdf_grid_2d"), o, ctx);
      });
  RegisterFunctionStage(r, "sdf_random_2d", Role::kSdfSampler, "2D SDF of the reference curve at `count` uniform points of [lo,hi]^2 (seeded)",
      ParamSchema()
          .Int("count", 441, "number of samples (441 = as many as a 20-cell grid)", 1, 100000000)
          .Double("lo", -1.0, "lower box bound on both axes")
          .Double("hi", 1.0, "upper box bound on both axes"),
      {}, [](Context& ctx, CaseData& d, const ParamMap& p) {
        d.samples = SampleSdfRandom2D(RequireReferenceCurve(d, "sdf_random_2d"), p.GetInt("count"),
                                      p.GetDouble("lo"), p.GetDouble("hi"), ctx);
      });
  RegisterFunctionStage(r, "marching_squares", Role::kSdfToMesh,
      "marching squares on 2D grid SDF samples (linear interpolation on edges; the 2D MC baseline of Fig. 5)",
      ParamSchema().Double("level", 0.0, "iso-value extracted"), {}, [](Context&, CaseData& d, const ParamMap& p) {
        const SdfSamples& sm = d.RequireSamples("marching_squares");
        if (sm.dim != 2) throw Error("marching_squares needs 2D samples; use marching_cubes for 3D");
        if (!sm.grid) throw Error("marching_squares needs samples on a regular grid (e.g. from sdf_grid_2d), got scattered samples");
        d.output_curve = ToPolyline(MarchingSquares(sm.values, *sm.grid, p.GetDouble("level")));
      });
  const Poisson2DOptions def;
  RegisterFunctionStage(r, "screened_poisson_2d", Role::kReconstructor,
      "2D screened Poisson (our own, on a regular grid): oriented 2D points -> closed polylines (RFTA's 2D sPSR)",
      ParamSchema()
          .Int("resolution", def.resolution,
               "grid cells per side; 0 = automatic: 4 sqrt(N) rounded up to a power of two, in [64, 1024]", 0, 4096)
          .Int("resolution_shift", def.resolution_shift, "added to the automatic power of two (-1 = half as fine)", -4, 4)
          .Double("screening", def.screening,
                  "screening weight alpha per unit curve length in cells (paper: 10; 0 = unscreened)", 0.0, 1e6)
          .Double("scale", def.scale, "grid side / largest extent of the points", 1.01, 16.0)
          .Double("smoothing", def.smoothing, "splatting radius of each normal, in multiples of its point spacing", 0.0, 16.0)
          .Int("neighbours", def.neighbours, "k of the k-nearest-neighbour density estimate", 1, 64),
      {"poisson2d_resolution"}, [](Context& ctx, CaseData& d, const ParamMap& p) {
        if (!d.points || !d.points->HasNormals())
          throw Error("screened_poisson_2d needs oriented points (points with normals) from an earlier stage");
        Poisson2DOptions o;
        o.resolution = static_cast<int>(p.GetInt("resolution"));
        o.resolution_shift = static_cast<int>(p.GetInt("resolution_shift"));
        o.screening = p.GetDouble("screening");
        o.scale = p.GetDouble("scale");
        o.smoothing = p.GetDouble("smoothing");
        o.neighbours = static_cast<int>(p.GetInt("neighbours"));
        Poisson2DInfo info;
        d.output_curve = ReconstructPoisson2D(*d.points, o, ctx, &info);
        d.SetMetric("poisson2d_resolution", info.resolution);
      });
  RegisterFunctionStage(r, "chamfer_2d", Role::kEvaluator,
      "the paper's Chamfer on curves: sqrt(mean d1^2) + sqrt(mean d2^2), nearest-sample distances between length-uniform samples",
      ParamSchema().Int("samples", 100000, "length-uniform samples per curve (sampling floor ~2e-5 at 10^5)", 1, 100000000),
      {"chamfer_2d"}, [](Context& ctx, CaseData& d, const ParamMap& p) {
        d.SetMetric("chamfer_2d", ChamferCurves(RequireOutputCurve(d, "chamfer_2d"), RequireReferenceCurve(d, "chamfer_2d"),
                                                p.GetInt("samples"), ctx.StreamSeed("chamfer_2d")));
      });
  RegisterFunctionStage(r, "hausdorff_2d", Role::kEvaluator,
      "two-sided Hausdorff between curves: max over vertices and length-uniform samples of each to the other curve",
      ParamSchema().Int("samples", 100000, "extra length-uniform samples per curve (0 = vertices only, the paper's bound)", 0,
                        100000000),
      {"hausdorff_2d"}, [](Context& ctx, CaseData& d, const ParamMap& p) {
        d.SetMetric("hausdorff_2d", HausdorffCurves(RequireOutputCurve(d, "hausdorff_2d"),
                                                    RequireReferenceCurve(d, "hausdorff_2d"), p.GetInt("samples"),
                                                    ctx.StreamSeed("hausdorff_2d")));
      });
  RegisterFunctionStage(r, "e_sdf_2d", Role::kEvaluator,
      "the paper's SDF energy on curves: 1000 * mean_i (|s_i| - dist(p_i, output curve))^2 over the 2D input samples",
      ParamSchema(), {"e_sdf_2d"}, [](Context&, CaseData& d, const ParamMap&) {
        d.SetMetric("e_sdf_2d", EnergySdf2D(d.RequireSamples("e_sdf_2d"), RequireOutputCurve(d, "e_sdf_2d")));
      });
  RegisterFunctionStage(r, "topology_2d", Role::kEvaluator,
      "output curve structure: components, closed components, open ends, branch vertices, holes (clockwise loops)",
      ParamSchema(),
      {"out_curve_components", "out_curve_closed_components", "out_curve_open_ends", "out_curve_branch_vertices",
       "out_curve_holes", "out_curve_edges"},
      [](Context&, CaseData& d, const ParamMap&) {
        const Polyline& c = RequireOutputCurve(d, "topology_2d");
        const CurveTopology t = ComputeCurveTopology(c);
        d.SetMetric("out_curve_components", t.components);
        d.SetMetric("out_curve_closed_components", t.closed_components);
        d.SetMetric("out_curve_open_ends", t.open_ends);
        d.SetMetric("out_curve_branch_vertices", t.branch_vertices);
        d.SetMetric("out_curve_holes", t.holes);
        d.SetMetric("out_curve_edges", c.NumEdges());
      });
}

}  // namespace arcs
