// screened_poisson: oriented points -> mesh by screened Poisson surface
// reconstruction (Kazhdan & Hoppe 2013; PCL's port), the reconstructor RFTA
// uses. Defaults follow the official RFTA call where PCL has the parameter.
#include "framework/reconstruct/poisson.h"
#include "framework/rfta/arc_projector.h"
#include "framework/rfta/sphere_carve.h"
#include "registry/bind.h"
#include "stages/builtin.h"

namespace arcs {

namespace {

Binder<PoissonOptions> ScreenedPoissonParams() {
  using O = PoissonOptions;
  return Binder<O>()
      .Int("depth", &O::depth,
           "maximum octree depth (2-12); 0 = automatic: finest cell ~ half the point spacing, clamped to [6, 10]",
           Closed(0, 12))
      .Int("depth_offset", &O::depth_offset,
           "added to the automatic depth (depth 0): -1/-2 = coarser and faster (RFTA's fine-tuning)", Closed(-8, 4))
      .Int("min_depth", &O::min_depth, "depth up to which the octree is complete (PoissonRecon fullDepth)",
           Closed(0, 12))
      .Double("point_weight", &O::point_weight,
              "screening weight (PCL's scale: 400 here ~ PoissonRecon's 10 in RFTA, measured; 0 = unscreened)",
              Closed(0.0, 1e6))
      .Double("samples_per_node", &O::samples_per_node,
              "minimum points per octree leaf (RFTA: 1.5; 15-20 for noisy points)", Closed(0.5, 100.0))
      .Double("scale", &O::scale, "reconstruction cube side / bounding-box extent of the points", Closed(1.01, 16.0))
      .Bool("manifold", &O::manifold, "split marching-cubes polygons at their barycentre (manifold output)")
      .Int("threads", &O::threads,
           "OpenMP threads inside PCL; only 1 is deterministic (set OMP_WAIT_POLICY=PASSIVE for more)",
           Closed(1, 256))
      .Int("open_retries", &O::open_retries,
           "an open output is solved again with a 4x weaker point weight, up to this many times (0 = never)",
           Closed(0, 10))
      .Enum("backend", &O::backend, kPoissonBackendNames,
            "pcl: pcl::Poisson (PoissonRecon ~v5 port, FEM degree 2); open3d: Open3D 0.16's PoissonRecon 12 "
            "(FEM degree 1, Neumann, 1.5 samples/node, area-normalised weight fixed at 2; depth, scale, threads "
            "only); arcs: our own (FEM degree 1, Neumann, area-normalised weight, warm-startable; docs/poisson.md)")
      .Int("cg_iters", &O::cg_iters, "backend arcs: conjugate-gradient steps per octree level (cap)",
           Closed(1, 10000))
      .Double("cg_accuracy", &O::cg_accuracy, "backend arcs: relative residual the CG stops at", Open(0.0, 1.0))
      .Double("base_accuracy", &O::base_accuracy,
              "backend arcs: relative residual of the complete level's multigrid-preconditioned CG "
              "(PoissonRecon: one V-cycle)",
              Open(0.0, 1.0))
      .Enum("fine_solver", &O::fine_solver, kSpsrFineSolverNames,
            "backend arcs: the levels above the complete one: cg_jacobi (CG, diagonal preconditioner), "
            "cg_gauss_seidel (CG, symmetric 8-colour Gauss-Seidel preconditioner), gauss_seidel (gs_iters "
            "8-colour Gauss-Seidel sweeps, PoissonRecon's cascadic relaxation)")
      .Int("gs_iters", &O::gs_iters, "backend arcs, fine_solver gauss_seidel: sweeps per level (PoissonRecon: 8)",
           Closed(1, 10000))
      .Double("extract_quantile", &O::extract_quantile,
              "backend arcs: marching cubes at the samples' octree depth at this quantile, rounded up (1 = finest)",
              Closed(0.0, 1.0))
      .Double("extract_max_cell", &O::extract_max_cell,
              "backend arcs: when > 0, marching cubes no finer than cells of this side (input units; 0 = the "
              "quantile's level); rfta sets it for its tuning surfaces from tuning_cell",
              Closed(0.0, 1e9))
      .Enum("normal_splat", &O::normal_splat, kSpsrNormalSplatNames,
            "backend arcs: where a sample's normal goes at fractional depth d: split = 1-frac(d) at floor(d), "
            "frac(d) at floor(d)+1 (PoissonRecon 12); ceil = all at ceil(d) (PoissonRecon 16.01/18.04, the "
            "official RFTA's call)")
      .Double("density_scale", &O::density_scale,
              "backend arcs: multiplies the samples' density estimate (1.5: a planar sheet then reads its "
              "samples per node area on average, as PoissonRecon's normalised kernel)",
              Closed(0.1, 10.0))
      .Enum("iso_weight", &O::iso_weight, kSpsrIsoWeightNames,
            "backend arcs: the iso-value is the mean of the solution at the samples weighted by their areas "
            "(area) or alike (count: PoissonRecon's, by merged point count)")
      .Enum("screen_samples", &O::screen_samples, kSpsrScreenSamplesNames,
            "backend arcs: the points that screen each octree level: each = every sample at its position; "
            "merged = the samples of one cell as one point at their mean, weighted by their count "
            "(PoissonRecon's interpolation info)")
      .Bool("warm_start", &O::warm_start,
            "backend arcs: a repeated call for one case (RFTA's fine-tuning) starts from the previous solution")
      .Bool("area_normalized", &O::area_normalized,
            "point_weight in PoissonRecon's units (the official RFTA: 10), i.e. scaled by the estimated sample "
            "area in the reconstruction cube; false: PCL's own units (divided by the point count)")
      .Bool("carve_spheres", &O::carve_spheres,
            "backend arcs, on a case with SDF samples (inside rfta): the balls of the samples with s > 0 (less "
            "RFTA's tol, 1e-4 of the samples' extent) are carved out of the solid before marching cubes; the "
            "samples certify them empty (rfta's `carve`; not in the paper)")
      .Double("carve_margin", &O::carve_margin,
              "carve_spheres: carve only where a ball is entered by more than this fraction of the samples' "
              "spacing (at least RFTA's tol)",
              Closed(0.0, 10.0))
      .Bool("carve_keep_voids", &O::carve_keep_voids,
            "carve_spheres: keep the closed voids carving alone makes (balls lying wholly inside the solid, "
            "components with no vertex on the Poisson surface); default: dropped");
}

void RunScreenedPoisson(Context& ctx, CaseData& d, const PoissonOptions& options, const ParamMap&) {
  if (!d.points->HasNormals()) throw Error("needs oriented points (points with normals), got points without normals");
  PoissonOptions o = options;
  if (o.carve_spheres) {
    if (!d.samples)
      throw Error("carve_spheres: needs the case's SDF samples (as inside rfta); this case has points only");
    if (o.backend != PoissonOptions::Backend::kArcs)
      throw Error("carve_spheres: only backend arcs can carve its surface");
    if (d.samples->dim != 3) throw Error("carve_spheres: needs 3D SDF samples");
    o.carve = OutsideSpheresCarve(*d.samples, CarveMargin(*d.samples, FeasibleSearchOptions{}.tol, o.carve_margin));
  }
  // Resolve the automatic depth here so the row records the depth used.
  if (o.depth == 0) o.depth = AutoPoissonDepth(*d.points, o);
  double used = o.point_weight;
  // The warm start, carried by a caller that runs this stage repeatedly.
  std::shared_ptr<void> state;
  if (d.nested.owner == "screened_poisson") state = d.nested.state;
  d.output = ReconstructPoisson(*d.points, o, ctx, &used, &state);
  if (state) d.nested = NestedState{std::move(state), "screened_poisson"};
  d.SetMetric("poisson_depth", o.depth);
  d.SetMetric("poisson_point_weight", used);
}

}  // namespace

void RegisterScreenedPoisson(Registry& r) {
  StageInfo s = DeclareStage(
      "screened_poisson", Role::kReconstructor,
      "screened Poisson surface reconstruction of the oriented points (PCL's PoissonRecon port; RFTA's sPSR)",
      {Slot::kPoints}, {Slot::kOutput}, k3D);
  BindStage<PoissonOptions>(s, ScreenedPoissonParams(), RunScreenedPoisson);
  s.outputs = {"poisson_depth", "poisson_point_weight"};
  r.Register(std::move(s));
}

}  // namespace arcs
