#include "framework/sdf/pseudo_sdf.h"

#include "framework/error.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

namespace arcs {

namespace {

struct Pose {
  Eigen::Matrix3d R;
  Vec3 shift;  // x -> R (x - c) + c + shift
};

std::vector<Pose> Poses(const Mesh& mesh, const SweepOptions& o, Vec3* center) {
  *center = 0.5 * (mesh.V.colwise().minCoeff() + mesh.V.colwise().maxCoeff()).transpose();
  std::vector<Pose> poses(o.steps);
  const Vec3 axis = o.axis.normalized();
  for (int k = 0; k < o.steps; ++k) {
    const double t = static_cast<double>(k) / (o.steps - 1);
    poses[k].R = Eigen::AngleAxisd(t * o.angle_deg * M_PI / 180.0, axis).toRotationMatrix();
    poses[k].shift = t * o.translation;
  }
  return poses;
}

}  // namespace

void SweepOptions::Check() const {
  ARCS_CHECK_OPTION(steps >= 2 && steps <= 4096, "steps", steps, "in [2, 4096]");
  if (!translation.allFinite()) throw OptionError("translation: must be finite");
  ARCS_CHECK_OPTION(std::isfinite(angle_deg), "angle_deg", angle_deg, "finite");
  if (angle_deg != 0.0 && !(axis.norm() > 0)) throw OptionError("axis: must be a non-zero vector");
}

Mesh SweepPoses(const Mesh& mesh, const SweepOptions& o) {
  o.Check();
  if (mesh.Empty()) throw Error("sweep: the mesh is empty");
  Vec3 c;
  const auto poses = Poses(mesh, o, &c);
  Mesh out;
  const int nv = mesh.NumVertices(), nf = mesh.NumFaces();
  out.V.resize(static_cast<Eigen::Index>(nv) * o.steps, 3);
  out.F.resize(static_cast<Eigen::Index>(nf) * o.steps, 3);
  for (int k = 0; k < o.steps; ++k) {
    for (int v = 0; v < nv; ++v)
      out.V.row(k * nv + v) = (poses[k].R * (mesh.V.row(v).transpose() - c) + c + poses[k].shift).transpose();
    out.F.middleRows(static_cast<Eigen::Index>(k) * nf, nf) = mesh.F.array() + k * nv;
  }
  return out;
}

VectorXd SweptSignedDistance(const Mesh& mesh, const SweepOptions& o, const MatrixX3d& points, SdfSign sign) {
  o.Check();
  if (mesh.Empty()) throw Error("sweep: the mesh is empty");
  Vec3 c;
  const auto poses = Poses(mesh, o, &c);
  // One SignedDistance call (one BVH and winding-number hierarchy) for a
  // block of poses at a time, at most ~4M query points per block.
  const Eigen::Index n = points.rows();
  VectorXd best = VectorXd::Constant(n, std::numeric_limits<double>::infinity());
  if (n == 0) return best;
  const int per_block = static_cast<int>(std::clamp<Eigen::Index>(4000000 / n, 1, o.steps));
  for (int k0 = 0; k0 < o.steps; k0 += per_block) {
    const int k1 = std::min(o.steps, k0 + per_block);
    MatrixX3d local((k1 - k0) * n, 3);
    for (int k = k0; k < k1; ++k) {
      // The posed solid contains x iff the mesh contains its pre-image.
      const Pose& p = poses[k];
      for (Eigen::Index i = 0; i < n; ++i)
        local.row((k - k0) * n + i) = (p.R.transpose() * (points.row(i).transpose() - c - p.shift) + c).transpose();
    }
    const VectorXd s = SignedDistance(mesh, local, sign);
    for (int k = k0; k < k1; ++k) best = best.cwiseMin(s.segment((k - k0) * n, n));
  }
  return best;
}

SdfSamples SampleSweptSdfGrid(const Mesh& mesh, const SweepOptions& sweep, const SdfGridOptions& grid,
                              const Context& ctx) {
  sweep.Check();
  grid.Check();
  SdfGridOptions layout = grid;
  layout.inside = SdfInside::kWinding;  // values replaced below: no voxelization
  SdfSamples out = SampleSdfGrid(mesh, layout, ctx);  // the layout (and pose 0's values)
  ctx.CheckStop();
  const MatrixX3d P = out.points;
  out.values = SweptSignedDistance(mesh, sweep, P, grid.sign);
  out.bound_sign = -1;
  return out;
}

}  // namespace arcs
