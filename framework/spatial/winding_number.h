// Generalized winding number of a triangle mesh (Jacobson et al. 2013; the
// per-triangle solid angle with atan2 as in Van Oosterom & Strackee, which is
// also Alg. 1 of the differentiable-voxelization paper). w = 1 inside a closed
// outward-oriented mesh, 0 outside, 1/2 on the surface.
#pragma once

#include "framework/types.h"

#include <memory>

namespace arcs {

// Signed solid angle of triangle (a, b, c) seen from q, divided by 4*pi.
double TriangleSolidAngleOver4Pi(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& q);

// Exact winding number: sum over all faces (O(#F) per query), with a
// vectorisable atan2 accurate to a few ulp. Throws InputError on a face index
// outside [0, #V).
double WindingNumberExact(const Mesh& mesh, const Vec3& q);
// Exact winding numbers for every row of Q, parallel over queries.
VectorXd WindingNumbersExact(const Mesh& mesh, const MatrixX3d& Q);

// Hierarchical ("fast") winding number: exact near field, Taylor far field
// (Barill et al. 2018) for clusters whose distance from q exceeds `beta`
// times their radius. Near the surface the exact near field dominates, so the
// inside test w > 0.5 agrees with the exact sum (checked on the tiny and bench
// meshes); the far-field error is largest at centres of curvature of large
// smooth regions.
// Options of FastWindingNumber (defined outside the class so that `= {}` can be
// used as a default argument inside it; use it as FastWindingNumber::Options).
struct FastWindingNumberOptions {
  double beta = 2.0;  // far-field acceptance ratio (distance / cluster radius); larger = more exact
  // Far-field Taylor order as in Barill et al. 2018: 0 = dipole (area-weighted
  // normal sum), 1 = + first moments, 2 = + second moments (their choice).
  int expansion_order = 2;
  void Check() const;
};

class FastWindingNumber {
 public:
  using Options = FastWindingNumberOptions;
  explicit FastWindingNumber(const Mesh& mesh, const Options& options = {});
  ~FastWindingNumber();
  FastWindingNumber(FastWindingNumber&&) noexcept;
  FastWindingNumber& operator=(FastWindingNumber&&) noexcept;

  double Eval(const Vec3& q) const;
  // Parallel over rows of Q; deterministic.
  VectorXd Eval(const MatrixX3d& Q) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace arcs
