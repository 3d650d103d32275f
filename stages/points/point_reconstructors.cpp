// Point-cloud reconstructors (role reconstructor: data.points -> data.output):
// ball_pivoting (Open3D), alpha_shape and advancing_front (CGAL). Each is
// interchangeable with screened_poisson in any YAML, including as RFTA's
// `reconstructor` / `tuning_reconstructor`. Decisions and measurements:
// docs/point_reconstructors.md.
#include "framework/points/point_reconstructors.h"
#include "stages/builtin.h"

namespace arcs {

namespace {
const PointCloud& RequirePoints(const CaseData& d, const char* who) {
  if (!d.points || d.points->Size() == 0)
    throw Error(std::string(who) + " needs a point cloud from the dataset (kind: points) or an earlier stage");
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
}  // namespace

void RegisterPointReconstructors(Registry& r) {
  {
    StageInfo s;
    s.name = "ball_pivoting";
    s.role = Role::kReconstructor;
    s.doc = "ball pivoting (Bernardini et al. 1999; Open3D) on oriented points; radii r, 2r, 4r, ... from the spacing";
    const BallPivotingOptions def;
    s.params
        .Double("radius", def.radius, "smallest ball radius; 0 = radius_factor x point spacing (mean nearest-neighbour distance)",
                0.0, 1e30)
        .Double("radius_factor", def.radius_factor, "automatic radius in point spacings (3: few small holes on uniform samples, measured)",
                0.1, 100.0)
        .Int("levels", def.levels, "number of radii r, 2r, 4r, ... (passes with growing balls)", 1, 8);
    s.outputs = kOutputs;
    s.factory = FunctionStage([](Context& ctx, CaseData& d, const ParamMap& p) {
      BallPivotingOptions o;
      o.radius = p.GetDouble("radius");
      o.radius_factor = p.GetDouble("radius_factor");
      o.levels = static_cast<int>(p.GetInt("levels"));
      PointReconstructionReport rep;
      d.output = ReconstructBallPivoting(RequirePoints(d, "ball_pivoting"), o, ctx, &rep);
      SetReport(d, rep);
    });
    r.Register(std::move(s));
  }
  {
    StageInfo s;
    s.name = "alpha_shape";
    s.role = Role::kReconstructor;
    s.doc = "alpha shape (Edelsbrunner & Muecke 1994; CGAL Alpha_shape_3): boundary of the regularized solid, wound outward";
    const AlphaShapeOptions def;
    s.params.Double("radius", def.radius, "alpha as a radius (CGAL's alpha is its square); 0 = automatic (rule)", 0.0, 1e30)
        .Choice("rule", def.rule, {"spacing", "optimal"},
                "automatic alpha: radius_factor x CGAL's optimal alpha radius (smallest single solid containing every point), or x the point spacing")
        .Double("radius_factor", def.radius_factor, "multiplier of the automatic base radius (1.2 x optimal: closed manifold on sphere/torus samples, measured)", 0.1, 1000.0);
    s.outputs = kOutputs;
    s.factory = FunctionStage([](Context& ctx, CaseData& d, const ParamMap& p) {
      AlphaShapeOptions o;
      o.radius = p.GetDouble("radius");
      o.rule = p.GetString("rule");
      o.radius_factor = p.GetDouble("radius_factor");
      PointReconstructionReport rep;
      d.output = ReconstructAlphaShape(RequirePoints(d, "alpha_shape"), o, ctx, &rep);
      SetReport(d, rep);
    });
    r.Register(std::move(s));
  }
  {
    StageInfo s;
    s.name = "advancing_front";
    s.role = Role::kReconstructor;
    s.doc = "advancing front surface reconstruction (Cohen-Steiner & Da 2004; CGAL): manifold, oriented; normals optional";
    const AdvancingFrontOptions def;
    s.params
        .Double("radius_ratio_bound", def.radius_ratio_bound,
                "reject candidate facets larger than this multiple of their neighbours (CGAL default)", 1.0, 1000.0)
        .Double("beta", def.beta, "sliver angle bound in radians (CGAL default 0.52)", 0.0, 1.5707963267948966);
    s.outputs = kOutputs;
    s.factory = FunctionStage([](Context& ctx, CaseData& d, const ParamMap& p) {
      AdvancingFrontOptions o;
      o.radius_ratio_bound = p.GetDouble("radius_ratio_bound");
      o.beta = p.GetDouble("beta");
      PointReconstructionReport rep;
      d.output = ReconstructAdvancingFront(RequirePoints(d, "advancing_front"), o, ctx, &rep);
      SetReport(d, rep);
    });
    r.Register(std::move(s));
  }
}

}  // namespace arcs
