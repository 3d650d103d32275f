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

// Exact winding number: sum over all faces (O(#F) per query).
double WindingNumberExact(const Mesh& mesh, const Vec3& q);
// Exact winding numbers for every row of Q, parallel over queries.
VectorXd WindingNumbersExact(const Mesh& mesh, const MatrixX3d& Q);

// Hierarchical ("fast") winding number: exact near field, dipole/Taylor far
// field for clusters whose distance exceeds `beta` times their radius.
// Options of FastWindingNumber (defined outside the class so that `= {}` can be
// used as a default argument inside it; use it as FastWindingNumber::Options).
struct FastWindingNumberOptions {
  double beta = 2.0;  // far-field acceptance ratio (distance / cluster radius); larger = more exact
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
