// Queries on a 2D polyline (z = 0): closest point on its segments (a
// bounding-volume hierarchy over the segments) and inside/outside by the 2D
// generalised winding number. These serve the 2D SDF (sdf2d.h), the 2D
// metrics and the fine-tuner's 2D surface (rfta/fine_tune.h).
#pragma once

#include "framework/types.h"

#include <limits>
#include <memory>

namespace arcs {

class SegmentBvh {
 public:
  struct Hit {
    double sq_dist = std::numeric_limits<double>::infinity();
    Vec3 point = Vec3::Zero();
    int edge = -1;  // -1: the curve has no edges
  };
  // Builds the hierarchy over the edges of `curve` (copied; zero-length edges
  // are points). Throws InputError on an edge index outside [0, #V).
  explicit SegmentBvh(const Polyline& curve);
  ~SegmentBvh();
  SegmentBvh(SegmentBvh&&) noexcept;
  SegmentBvh& operator=(SegmentBvh&&) noexcept;

  // Closest point to q (its z is ignored; the answer has z = 0). Among
  // equidistant edges the lowest index wins, so answers do not depend on the
  // traversal order.
  Hit Closest(const Vec3& q) const;
  // Closest(q) for every row of Q, in parallel; identical at any thread count.
  // Outputs may be null; they are resized.
  void ClosestPoints(const MatrixX3d& Q, VectorXd* sq_dist, MatrixX3d* points = nullptr,
                     Eigen::VectorXi* edges = nullptr) const;

  const Polyline& curve() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The generalised winding number of the curve around q: the sum over the
// edges of the signed angle they subtend at q, over 2 pi. For closed curves
// oriented inside-left it is 1 inside an outer boundary, 0 outside and in a
// hole; "inside" means w > 0.5. A query on an edge gets a value near 0.5.
double WindingNumber2D(const Polyline& curve, const Vec3& q);
// For every row of Q, in parallel (deterministic).
VectorXd WindingNumbers2D(const Polyline& curve, const MatrixX3d& Q);

}  // namespace arcs
