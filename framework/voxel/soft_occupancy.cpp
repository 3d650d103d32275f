// Per-triangle winding-number terms with analytic gradients, and dense sums.
#include "framework/voxel/soft_occupancy.h"

#include "framework/error.h"
#include "framework/spatial/topology.h"
#include "framework/spatial/winding_number.h"
#include "framework/util/parallel.h"
#include "framework/voxel/soft_kernels.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace arcs {

const char* WindingFormName(WindingForm v) {
  for (const auto& e : kWindingFormNames)
    if (e.value == v) return e.name;
  return "?";
}

WindingForm ParseWindingForm(const std::string& name) {
  return EnumFromName(std::span<const EnumName<WindingForm>>(kWindingFormNames), name);
}

const char* OccupancyMapName(OccupancyMap v) {
  for (const auto& e : kOccupancyMapNames)
    if (e.value == v) return e.name;
  return "?";
}

OccupancyMap ParseOccupancyMap(const std::string& name) {
  return EnumFromName(std::span<const EnumName<OccupancyMap>>(kOccupancyMapNames), name);
}

void SoftOccupancyOptions::Check() const {
  ARCS_CHECK_OPTION(sharpness > 0.0 && sharpness <= 1e6, "sharpness", sharpness, "in (0, 1e6]");
  ARCS_CHECK_OPTION(std::isfinite(softening) && softening >= 0.0, "softening", softening,
                    "a finite number >= 0");
}

double SolidAngleTermGrad(const Vec3& v0, const Vec3& v1, const Vec3& v2, const Vec3& q,
                          Vec3* grad) {
  const Vec3 a[3] = {v0 - q, v1 - q, v2 - q};
  double l[3];
  Vec3 e[3];
  for (int j = 0; j < 3; ++j) {
    l[j] = a[j].norm();
    e[j] = l[j] > 0.0 ? Vec3(a[j] / l[j]) : Vec3::Zero();
  }
  const double alpha = e[0].dot(e[1].cross(e[2]));
  const double beta = 1.0 + e[0].dot(e[1]) + e[1].dot(e[2]) + e[2].dot(e[0]);
  constexpr double kInv2Pi = 0.5 / std::numbers::pi;
  const bool on_vertex = l[0] == 0.0 || l[1] == 0.0 || l[2] == 0.0;
  const double w = on_vertex ? 0.0 : std::atan2(alpha, beta) * kInv2Pi;
  if (grad) {
    const double r2 = alpha * alpha + beta * beta;
    if (on_vertex || !(r2 > 0.0)) {
      grad[0] = grad[1] = grad[2] = Vec3::Zero();
    } else {
      // d atan2(α, β) = (β dα - α dβ) / (α² + β²); dα/de0 = e1 × e2 (cyclic),
      // dβ/de0 = e1 + e2 (cyclic); de/da = (I - e eᵀ) / |a|.
      const double ga = beta / r2 * kInv2Pi, gb = -alpha / r2 * kInv2Pi;
      for (int j = 0; j < 3; ++j) {
        const Vec3& e1 = e[(j + 1) % 3];
        const Vec3& e2 = e[(j + 2) % 3];
        const Vec3 ge = ga * e1.cross(e2) + gb * (e1 + e2);
        grad[j] = (ge - ge.dot(e[j]) * e[j]) / l[j];
      }
    }
  }
  return w;
}

double NaiveTermGrad(const Vec3& v0, const Vec3& v1, const Vec3& v2, const Vec3& q, Vec3* grad,
                     double softening) {
  constexpr double kInv4Pi = 0.25 / std::numbers::pi;
  const Vec3 n = 0.5 * (v1 - v0).cross(v2 - v0);  // area vector N = n Δ
  const Vec3 r = (v0 + v1 + v2) / 3.0 - q;        // E_q(c) direction
  const double r2 = r.squaredNorm() + softening * softening;
  if (!(r2 > 0.0)) {
    if (grad) grad[0] = grad[1] = grad[2] = Vec3::Zero();
    return 0.0;
  }
  const double inv3 = 1.0 / (r2 * std::sqrt(r2));
  const double nr = n.dot(r);
  if (grad) {
    // ∂w/∂N = r/|r|³, ∂w/∂r = N/|r|³ - 3 (N·r) r/|r|⁵; N = ½(v0×v1 + v1×v2 + v2×v0)
    // gives ∂(g·N)/∂v0 = ½ g × (v2 - v1) (cyclic); ∂r/∂v_j = I/3.
    const Vec3 gn = kInv4Pi * inv3 * r;
    const Vec3 gc = kInv4Pi * inv3 * (n - (3.0 * nr / r2) * r) / 3.0;
    grad[0] = 0.5 * gn.cross(v2 - v1) + gc;
    grad[1] = 0.5 * gn.cross(v0 - v2) + gc;
    grad[2] = 0.5 * gn.cross(v1 - v0) + gc;
  }
  return kInv4Pi * nr * inv3;
}

VectorXd WindingNumbers(const Mesh& mesh, const MatrixX3d& Q, WindingForm form, double softening) {
  if (form == WindingForm::kSolidAngle) return WindingNumbersExact(mesh, Q);
  CheckMeshIndices(mesh, "WindingNumbers", /*finite=*/true);
  ARCS_CHECK_OPTION(std::isfinite(softening) && softening >= 0.0, "softening", softening, "a finite number >= 0");
  const voxel_detail::NaiveFaces faces(mesh, softening);
  VectorXd w(Q.rows());
  const std::int64_t nf = std::max(1, mesh.NumFaces());
  ParallelFor(
      Q.rows(),
      [&](std::int64_t begin, std::int64_t end) {
        for (std::int64_t i = begin; i < end; ++i) w[i] = faces.Sum(Q(i, 0), Q(i, 1), Q(i, 2));
      },
      std::max<std::int64_t>(1, 200000 / nf));
  return w;
}

double OccupancyFromWinding(double w, const SoftOccupancyOptions& options, double* dodw) {
  switch (options.map) {
    case OccupancyMap::kIdentity:
      if (dodw) *dodw = 1.0;
      return w;
    case OccupancyMap::kClamp:
      if (dodw) *dodw = (w > 0.0 && w < 1.0) ? 1.0 : 0.0;
      return std::clamp(w, 0.0, 1.0);
    case OccupancyMap::kSigmoid: {
      const double o = 1.0 / (1.0 + std::exp(-options.sharpness * (w - 0.5)));
      if (dodw) *dodw = options.sharpness * o * (1.0 - o);
      return o;
    }
  }
  return w;
}

VectorXd SoftOccupancy(const Mesh& mesh, const MatrixX3d& Q, const SoftOccupancyOptions& options) {
  options.Check();
  VectorXd o = WindingNumbers(mesh, Q, options.form, options.softening);
  for (Eigen::Index i = 0; i < o.size(); ++i) o[i] = OccupancyFromWinding(o[i], options, nullptr);
  return o;
}

}  // namespace arcs
