// Point-cloud reconstructors (role reconstructor: data.points -> data.output):
// ball_pivoting (Open3D), alpha_shape and advancing_front (CGAL). Each is
// interchangeable with screened_poisson in any YAML, including as RFTA's
// `reconstructor` / `tuning_reconstructor`. Decisions and measurements:
// docs/point_reconstructors.md.
#include "framework/points/point_reconstructors.h"
#include "registry/bind.h"
#include "stages/builtin.h"

namespace arcs {

namespace {
// The contract guarantees a point cloud; an empty one is refused here.
const PointCloud& NonEmptyPoints(const CaseData& d) {
  if (d.points->Size() == 0) throw Error("the point cloud is empty");
  return *d.points;
}
void SetReport(CaseData& d, const PointReconstructionReport& r) {
  d.SetMetric("recon_points_used", r.points_used);
  d.SetMetric("recon_duplicates_removed", r.duplicates_removed);
  d.SetMetric("recon_spacing", r.spacing);
  d.SetMetric("recon_radius", r.radius);
}
const std::vector<std::string> kOutputs = {"recon_points_used", "recon_duplicates_removed", "recon_spacing",
                                           "recon_radius"};

Binder<BallPivotingOptions> BallPivotingParams() {
  using O = BallPivotingOptions;
  return Binder<O>()
      .Double("radius", &O::radius,
              "smallest ball radius; 0 = radius_factor x point spacing (mean nearest-neighbour distance)",
              Closed(0.0, 1e30))
      .Double("radius_factor", &O::radius_factor,
              "automatic radius in point spacings (3: few small holes on uniform samples, measured)",
              Closed(0.1, 100.0))
      .Int("levels", &O::levels, "number of radii r, 2r, 4r, ... (passes with growing balls)", Closed(1, 8));
}

void RunBallPivoting(Context& ctx, CaseData& d, const BallPivotingOptions& o, const ParamMap&) {
  PointReconstructionReport rep;
  d.output = ReconstructBallPivoting(NonEmptyPoints(d), o, ctx, &rep);
  SetReport(d, rep);
}

// AlphaShapeOptions::rule is a string (its Check() refuses other names): a
// choice of the schema, decoded into the struct by the stage.
Binder<AlphaShapeOptions> AlphaShapeParams() {
  using O = AlphaShapeOptions;
  const O def;
  return Binder<O>()
      .Double("radius", &O::radius, "alpha as a radius (CGAL's alpha is its square); 0 = automatic (rule)",
              Closed(0.0, 1e30))
      .Choice("rule", def.rule, {"spacing", "optimal"},
              "automatic alpha: radius_factor x CGAL's optimal alpha radius (smallest single solid containing every "
              "point), or x the point spacing")
      .Double("radius_factor", &O::radius_factor,
              "multiplier of the automatic base radius (1.2 x optimal: closed manifold on sphere/torus samples, "
              "measured)",
              Closed(0.1, 1000.0));
}

void RunAlphaShape(Context& ctx, CaseData& d, const AlphaShapeOptions& bound, const ParamMap& p) {
  AlphaShapeOptions o = bound;
  o.rule = p.GetString("rule");
  PointReconstructionReport rep;
  d.output = ReconstructAlphaShape(NonEmptyPoints(d), o, ctx, &rep);
  SetReport(d, rep);
}

Binder<AdvancingFrontOptions> AdvancingFrontParams() {
  using O = AdvancingFrontOptions;
  return Binder<O>()
      .Double("radius_ratio_bound", &O::radius_ratio_bound,
              "reject candidate facets larger than this multiple of their neighbours (CGAL default)",
              Closed(1.0, 1000.0))
      .Double("beta", &O::beta, "sliver angle bound in radians (CGAL default 0.52)",
              Closed(0.0, 1.5707963267948966));
}

void RunAdvancingFront(Context& ctx, CaseData& d, const AdvancingFrontOptions& o, const ParamMap&) {
  PointReconstructionReport rep;
  d.output = ReconstructAdvancingFront(NonEmptyPoints(d), o, ctx, &rep);
  SetReport(d, rep);
}

template <class O>
void Add(Registry& r, const char* name, const char* doc, const Binder<O>& params, BoundStageFn<O> run) {
  StageInfo s = DeclareStage(name, Role::kReconstructor, doc, {Slot::kPoints}, {Slot::kOutput}, k3D);
  s.outputs = kOutputs;
  BindStage<O>(s, params, std::move(run));
  r.Register(std::move(s));
}
}  // namespace

void RegisterPointReconstructors(Registry& r) {
  Add<BallPivotingOptions>(
      r, "ball_pivoting",
      "ball pivoting (Bernardini et al. 1999; Open3D) on oriented points; radii r, 2r, 4r, ... from the spacing",
      BallPivotingParams(), RunBallPivoting);
  Add<AlphaShapeOptions>(
      r, "alpha_shape",
      "alpha shape (Edelsbrunner & Muecke 1994; CGAL Alpha_shape_3): boundary of the regularized solid, wound outward",
      AlphaShapeParams(), RunAlphaShape);
  Add<AdvancingFrontOptions>(
      r, "advancing_front",
      "advancing front surface reconstruction (Cohen-Steiner & Da 2004; CGAL): manifold, oriented; normals optional",
      AdvancingFrontParams(), RunAdvancingFront);
}

}  // namespace arcs
