// Closest points on polylines (SegmentBvh) and 2D winding numbers.
#include "framework/geometry/curves.h"
#include "framework/spatial/polyline_query.h"
#include "framework/util/rng.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace arcs {
namespace {

TEST(PolylineQuery, ClosestPointMatchesBruteForceAndWindingNumbers) {
  const Polyline c = MakeBuiltinCurve("star", 300);
  const SegmentBvh bvh(c);
  Rng rng(3);
  for (int k = 0; k < 300; ++k) {
    const Vec3 q(rng.Uniform(-0.8, 0.8), rng.Uniform(-0.8, 0.8), 0);
    double best = 1e300;
    for (int e = 0; e < c.NumEdges(); ++e) {
      const Eigen::Vector2d a = c.V.row(c.E(e, 0)).head<2>(), b = c.V.row(c.E(e, 1)).head<2>();
      const double t = std::clamp((q.head<2>() - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
      best = std::min(best, (a + t * (b - a) - q.head<2>()).squaredNorm());
    }
    const SegmentBvh::Hit h = bvh.Closest(q);
    EXPECT_NEAR(h.sq_dist, best, 1e-15);
    EXPECT_NEAR((h.point - q).squaredNorm(), h.sq_dist, 1e-15);
  }
  const Polyline ann = MakeBuiltinCurve("annulus", 256);
  EXPECT_NEAR(WindingNumber2D(ann, Vec3(0, 0, 0)), 0.0, 1e-12);
  EXPECT_NEAR(WindingNumber2D(ann, Vec3(0.37, 0.05, 0)), 1.0, 1e-12);
  EXPECT_NEAR(WindingNumber2D(ann, Vec3(0.9, 0, 0)), 0.0, 1e-12);
}

}  // namespace
}  // namespace arcs
