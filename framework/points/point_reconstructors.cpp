#include "framework/points/point_reconstructors.h"

#include "framework/error.h"
#include "framework/points/backends.h"
#include "framework/points/point_utils.h"

#include <cmath>
#include <vector>

namespace arcs {

void BallPivotingOptions::Check() const {
  ARCS_CHECK_OPTION(radius >= 0 && radius <= 1e30, "radius", radius, "in [0, 1e30] (0 = automatic)");
  ARCS_CHECK_OPTION(radius_factor >= 0.1 && radius_factor <= 100, "radius_factor", radius_factor, "in [0.1, 100]");
  ARCS_CHECK_OPTION(levels >= 1 && levels <= 8, "levels", levels, "in [1, 8]");
}

void AlphaShapeOptions::Check() const {
  ARCS_CHECK_OPTION(radius >= 0 && radius <= 1e30, "radius", radius, "in [0, 1e30] (0 = automatic)");
  if (rule != "spacing" && rule != "optimal") throw OptionError("rule = " + rule + ": must be one of {spacing, optimal}");
  ARCS_CHECK_OPTION(radius_factor >= 0.1 && radius_factor <= 1000, "radius_factor", radius_factor, "in [0.1, 1000]");
}

void AdvancingFrontOptions::Check() const {
  ARCS_CHECK_OPTION(radius_ratio_bound >= 1 && radius_ratio_bound <= 1000, "radius_ratio_bound", radius_ratio_bound,
                    "in [1, 1000]");
  ARCS_CHECK_OPTION(beta >= 0 && beta <= M_PI / 2, "beta", beta, "in [0, pi/2]");
}

bool CgalReconstructorsAvailable() { return points_detail::CgalAvailable(); }
bool BallPivotingAvailable() { return points_detail::Open3dAvailable(); }

namespace {
Mesh Finish(Mesh m, const char* who, const Context& ctx) {
  ctx.CheckStop();
  m = CompactMesh(m);
  if (m.Empty())
    throw Error(std::string(who) + ": produced no faces (radius too small for the sampling, or too few points)");
  return m;
}
}  // namespace

Mesh ReconstructBallPivoting(const PointCloud& points, const BallPivotingOptions& o, const Context& ctx,
                             PointReconstructionReport* report) {
  o.Check();
  ctx.CheckStop();
  const PreparedPoints in = PrepareReconstructionInput(points, "ball_pivoting", /*need_normals=*/true);
  PointReconstructionReport rep;
  rep.points_used = in.cloud.Size();
  rep.duplicates_removed = in.duplicates_removed;
  rep.spacing = PointSpacing(in.cloud.P);
  rep.radius = o.radius > 0 ? o.radius : o.radius_factor * rep.spacing;
  std::vector<double> radii;
  for (int l = 0; l < o.levels; ++l) radii.push_back(rep.radius * std::ldexp(1.0, l));
  Mesh m = points_detail::Open3dBallPivoting(in.cloud.P, in.cloud.N, radii);
  m = Finish(std::move(m), "ball_pivoting", ctx);
  if (report) *report = rep;
  return m;
}

Mesh ReconstructAlphaShape(const PointCloud& points, const AlphaShapeOptions& o, const Context& ctx,
                           PointReconstructionReport* report) {
  o.Check();
  ctx.CheckStop();
  const PreparedPoints in = PrepareReconstructionInput(points, "alpha_shape", /*need_normals=*/false);
  PointReconstructionReport rep;
  rep.points_used = in.cloud.Size();
  rep.duplicates_removed = in.duplicates_removed;
  rep.spacing = PointSpacing(in.cloud.P);
  double alpha = o.radius;
  if (alpha == 0 && o.rule == "spacing") alpha = o.radius_factor * rep.spacing;
  double used_sq = 0;
  Mesh m = points_detail::CgalAlphaShape(in.cloud.P, alpha * alpha, &used_sq, o.radius_factor);
  rep.radius = std::sqrt(used_sq);
  m = Finish(std::move(m), "alpha_shape", ctx);
  if (report) *report = rep;
  return m;
}

Mesh ReconstructAdvancingFront(const PointCloud& points, const AdvancingFrontOptions& o, const Context& ctx,
                               PointReconstructionReport* report) {
  o.Check();
  ctx.CheckStop();
  const PreparedPoints in = PrepareReconstructionInput(points, "advancing_front", /*need_normals=*/false);
  PointReconstructionReport rep;
  rep.points_used = in.cloud.Size();
  rep.duplicates_removed = in.duplicates_removed;
  rep.spacing = PointSpacing(in.cloud.P);
  Mesh m = points_detail::CgalAdvancingFront(in.cloud.P, o.radius_ratio_bound, o.beta);
  rep.flipped_components = OrientComponents(&m, in.cloud.HasNormals() ? &in.cloud.N : nullptr);
  m = Finish(std::move(m), "advancing_front", ctx);
  if (report) *report = rep;
  return m;
}

}  // namespace arcs
