// Adjoint (vector–Jacobian) passes of the winding-number sums and the
// occupancy loss.
#include "framework/voxel/gradient.h"

#include "framework/error.h"
#include "framework/spatial/topology.h"
#include "framework/util/parallel.h"
#include "framework/voxel/soft_kernels.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace arcs {
namespace {

using voxel_detail::kInv4Pi;
using voxel_detail::NaiveFaces;

constexpr int kFaceBlock = 64;  // faces per adjoint task (fixed: results do not depend on threads)

// Naive form: per face, gN_f = Σ_q λ_q (c_f - q)/|c_f - q|³ and
// gc_f = Σ_q λ_q (N_f/|r|³ - 3 (N_f·r) r/|r|⁵), r = c_f - q (times 1/4π).
// Then ∂/∂v0 = ½ gN × (v2 - v1) + gc/3 (cyclic), as NaiveTermGrad.
void NaiveFaceAdjoints(const NaiveFaces& fc, const MatrixX3d& Q, const std::vector<int>& active,
                       const VectorXd& lambda, std::vector<double>* gface /* 6 per face */) {
  const std::int64_t nf = static_cast<std::int64_t>(fc.Size());
  const std::int64_t nblocks = (nf + kFaceBlock - 1) / kFaceBlock;
  ParallelFor(
      nblocks,
      [&](std::int64_t b0, std::int64_t b1) {
        for (std::int64_t b = b0; b < b1; ++b) {
          const std::int64_t s = b * kFaceBlock;
          const int m = static_cast<int>(std::min<std::int64_t>(kFaceBlock, nf - s));
          double gnx[kFaceBlock] = {}, gny[kFaceBlock] = {}, gnz[kFaceBlock] = {};
          double gcx[kFaceBlock] = {}, gcy[kFaceBlock] = {}, gcz[kFaceBlock] = {};
          const double *Nx = fc.nx.data() + s, *Ny = fc.ny.data() + s, *Nz = fc.nz.data() + s;
          const double *Cx = fc.cx.data() + s, *Cy = fc.cy.data() + s, *Cz = fc.cz.data() + s;
          for (int qi : active) {
            const double qx = Q(qi, 0), qy = Q(qi, 1), qz = Q(qi, 2), l = lambda[qi];
            for (int i = 0; i < m; ++i) {
              const double rx = Cx[i] - qx, ry = Cy[i] - qy, rz = Cz[i] - qz;
              const double r2 = rx * rx + ry * ry + rz * rz + fc.eps2;
              const double d = r2 * std::sqrt(r2);
              const double li3 = d > 0.0 ? l / d : 0.0;
              const double k = d > 0.0 ? 3.0 * (Nx[i] * rx + Ny[i] * ry + Nz[i] * rz) / r2 : 0.0;
              gnx[i] += li3 * rx, gny[i] += li3 * ry, gnz[i] += li3 * rz;
              gcx[i] += li3 * (Nx[i] - k * rx);
              gcy[i] += li3 * (Ny[i] - k * ry);
              gcz[i] += li3 * (Nz[i] - k * rz);
            }
          }
          for (int i = 0; i < m; ++i) {
            double* g = gface->data() + 6 * (s + i);
            g[0] = gnx[i], g[1] = gny[i], g[2] = gnz[i], g[3] = gcx[i], g[4] = gcy[i], g[5] = gcz[i];
          }
        }
      },
      1);
}

}  // namespace

MatrixX3d WindingNumberVjp(const Mesh& mesh, const MatrixX3d& Q, const VectorXd& lambda,
                           WindingForm form, double softening) {
  ARCS_CHECK_OPTION(std::isfinite(softening) && softening >= 0.0, "softening", softening, "a finite number >= 0");
  CheckMeshIndices(mesh, "WindingNumberVjp", /*finite=*/true);
  if (lambda.size() != Q.rows())
    throw Error("WindingNumberVjp: " + std::to_string(lambda.size()) + " weights for " +
                std::to_string(Q.rows()) + " queries");
  std::vector<int> active;
  for (Eigen::Index i = 0; i < lambda.size(); ++i)
    if (lambda[i] != 0.0) active.push_back(static_cast<int>(i));
  const int nf = mesh.NumFaces();
  MatrixX3d grad = MatrixX3d::Zero(mesh.NumVertices(), 3);
  if (form == WindingForm::kNaive) {
    const NaiveFaces fc(mesh, softening);
    std::vector<double> gface(6 * static_cast<std::size_t>(nf));
    NaiveFaceAdjoints(fc, Q, active, lambda, &gface);
    for (int f = 0; f < nf; ++f) {
      const double* g = gface.data() + 6 * f;
      const Vec3 gn = kInv4Pi * Vec3(g[0], g[1], g[2]);
      const Vec3 gc = (kInv4Pi / 3.0) * Vec3(g[3], g[4], g[5]);
      const int i0 = mesh.F(f, 0), i1 = mesh.F(f, 1), i2 = mesh.F(f, 2);
      const Vec3 v0 = mesh.V.row(i0), v1 = mesh.V.row(i1), v2 = mesh.V.row(i2);
      grad.row(i0) += (0.5 * gn.cross(v2 - v1) + gc).transpose();
      grad.row(i1) += (0.5 * gn.cross(v0 - v2) + gc).transpose();
      grad.row(i2) += (0.5 * gn.cross(v1 - v0) + gc).transpose();
    }
    return grad;
  }
  // Solid-angle form: per face, the scalar analytic gradient summed over queries.
  std::vector<double> gface(9 * static_cast<std::size_t>(nf));
  ParallelFor(
      nf,
      [&](std::int64_t f0, std::int64_t f1) {
        for (std::int64_t f = f0; f < f1; ++f) {
          const Vec3 v0 = mesh.V.row(mesh.F(f, 0)), v1 = mesh.V.row(mesh.F(f, 1)),
                     v2 = mesh.V.row(mesh.F(f, 2));
          Vec3 acc[3] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
          Vec3 g[3];
          for (int qi : active) {
            SolidAngleTermGrad(v0, v1, v2, Q.row(qi).transpose(), g);
            for (int j = 0; j < 3; ++j) acc[j] += lambda[qi] * g[j];
          }
          for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) gface[9 * f + 3 * j + k] = acc[j][k];
        }
      },
      std::max<std::int64_t>(1, 20000 / std::max<std::int64_t>(1, static_cast<std::int64_t>(active.size()))));
  for (int f = 0; f < nf; ++f)
    for (int j = 0; j < 3; ++j)
      grad.row(mesh.F(f, j)) += Eigen::RowVector3d(gface[9 * f + 3 * j], gface[9 * f + 3 * j + 1],
                                                   gface[9 * f + 3 * j + 2]);
  return grad;
}

const char* OccupancyLossName(OccupancyLossKind v) {
  for (const auto& e : kOccupancyLossNames)
    if (e.value == v) return e.name;
  return "?";
}

OccupancyLossKind ParseOccupancyLoss(const std::string& name) {
  return EnumFromName(std::span<const EnumName<OccupancyLossKind>>(kOccupancyLossNames), name);
}

double OccupancyLossTerm(double o, double t, OccupancyLossKind kind, double* dldo) {
  if (kind == OccupancyLossKind::kMse) {
    if (dldo) *dldo = 2.0 * (o - t);
    return (o - t) * (o - t);
  }
  constexpr double kEps = 1e-6;
  const double oc = std::clamp(o, kEps, 1.0 - kEps);
  if (dldo) *dldo = (o == oc) ? (oc - t) / (oc * (1.0 - oc)) : 0.0;
  return -(t * std::log(oc) + (1.0 - t) * std::log(1.0 - oc));
}

OccupancyLossResult OccupancyLoss(const Mesh& mesh, const MatrixX3d& Q, const VectorXd& target,
                                  const OccupancyLossOptions& options) {
  options.Check();
  if (Q.rows() == 0) throw Error("OccupancyLoss: no query points");
  if (target.size() != Q.rows())
    throw Error("OccupancyLoss: " + std::to_string(target.size()) + " target values for " +
                std::to_string(Q.rows()) + " queries");
  OccupancyLossResult r;
  r.winding = WindingNumbers(mesh, Q, options.occupancy.form, options.occupancy.softening);
  r.occupancy.resize(Q.rows());
  VectorXd lambda(Q.rows());
  const double inv_n = 1.0 / static_cast<double>(Q.rows());
  for (Eigen::Index i = 0; i < Q.rows(); ++i) {
    double dodw = 0.0, dldo = 0.0;
    r.occupancy[i] = OccupancyFromWinding(r.winding[i], options.occupancy, &dodw);
    r.loss += OccupancyLossTerm(r.occupancy[i], target[i], options.loss, &dldo);
    lambda[i] = dldo * dodw * inv_n;
  }
  r.loss *= inv_n;
  r.grad = WindingNumberVjp(mesh, Q, lambda, options.occupancy.form, options.occupancy.softening);
  return r;
}

}  // namespace arcs
