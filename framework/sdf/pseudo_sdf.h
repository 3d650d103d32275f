// Pseudo-SDFs (RFTA paper §5.3, Fig. 25): functions whose zero level set is
// a surface but whose values are not all distances. The paper's example is
// the swept volume of a moving solid, represented as in Sellán et al. 2021
// and Marschner et al. 2023 by the minimum over time of the moving solid's
// SDF. With the sweep discretised into K poses the swept solid is the union
// of the posed solids, and min_k s_k(x) is
//   * outside: exactly the distance to the union (distance to a union is the
//     minimum of the distances), and
//   * inside: only a lower bound of the depth (a point deep inside the union
//     but near the boundary of every single pose gets a small |s|).
// So the samples are marked bound_sign = -1: their inside spheres are empty
// of surface but need not be tangent to it.
#pragma once

#include "framework/context.h"
#include "framework/sdf/sdf_sampling.h"
#include "framework/types.h"

namespace arcs {

struct SweepOptions {
  // Pose k of K = steps (t = k / (K-1)): rotate by t * angle_deg about the
  // axis through the mesh's bounding-box centre, then translate by
  // t * translation. The solid at t = 0 is the mesh itself.
  Vec3 translation = Vec3(0.3, 0.0, 0.0);
  Vec3 axis = Vec3(0.0, 0.0, 1.0);
  double angle_deg = 0.0;
  int steps = 16;  // K >= 2
  void Check() const;
};

// The K posed copies of `mesh`, concatenated (a soup whose union is the
// discretised swept solid).
Mesh SweepPoses(const Mesh& mesh, const SweepOptions& options);

// The swept solid's pseudo-SDF at `points`: min over poses of the posed
// mesh's signed distance (sign by winding number, as SignedDistance).
VectorXd SweptSignedDistance(const Mesh& mesh, const SweepOptions& options, const MatrixX3d& points,
                             SdfSign sign = SdfSign::kFastWindingNumber);

// Grid samples (layout as SampleSdfGrid) of the swept pseudo-SDF, with
// bound_sign = -1.
SdfSamples SampleSweptSdfGrid(const Mesh& mesh, const SweepOptions& sweep, const SdfGridOptions& grid,
                              const Context& ctx);

}  // namespace arcs
