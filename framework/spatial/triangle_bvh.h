// Closest point on a triangle mesh: a bounding-volume hierarchy over the
// triangles with exact point-triangle distance at the leaves.
#pragma once

#include "framework/types.h"

#include <limits>
#include <memory>

namespace arcs {

class TriangleBvh {
 public:
  struct Hit {
    double sq_dist = std::numeric_limits<double>::infinity();
    Vec3 point = Vec3::Zero();
    int face = -1;  // -1: nothing found within the search radius
  };

  // Builds the hierarchy over `mesh` (the mesh is copied; degenerate faces are
  // allowed and handled as segments/points).
  explicit TriangleBvh(const Mesh& mesh);
  ~TriangleBvh();
  TriangleBvh(TriangleBvh&&) noexcept;
  TriangleBvh& operator=(TriangleBvh&&) noexcept;

  // Closest point to q among faces within sqrt(max_sq_dist) (exact, double).
  Hit Closest(const Vec3& q, double max_sq_dist = std::numeric_limits<double>::infinity()) const;

  // Closest points for every row of Q, in parallel; deterministic. Any of the
  // outputs may be null. Outputs are resized.
  void ClosestPoints(const MatrixX3d& Q, VectorXd* sq_dist, MatrixX3d* points = nullptr,
                     Eigen::VectorXi* faces = nullptr) const;

  const Mesh& mesh() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace arcs
