// Core geometry containers shared by every module.
//
// Conventions (used everywhere in arcs):
//  * Matrices are row-major in meaning: one row per vertex / point / sample.
//  * Meshes are triangle meshes; faces are counter-clockwise seen from outside
//    (outward normals, positive volume for a closed mesh).
//  * Signed distances are negative inside, positive outside.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace arcs {

using MatrixX3d = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
using MatrixX3i = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;
using MatrixXd = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using VectorXd = Eigen::VectorXd;
using Vec3 = Eigen::Vector3d;

// A triangle mesh. V: #V x 3 positions, F: #F x 3 zero-based vertex indices.
struct Mesh {
  MatrixX3d V;
  MatrixX3i F;
  int NumVertices() const { return static_cast<int>(V.rows()); }
  int NumFaces() const { return static_cast<int>(F.rows()); }
  bool Empty() const { return F.rows() == 0; }
};

// A point cloud, optionally with unit normals (N has 0 rows when absent).
struct PointCloud {
  MatrixX3d P;
  MatrixX3d N;
  bool HasNormals() const { return N.rows() == P.rows() && P.rows() > 0; }
  int Size() const { return static_cast<int>(P.rows()); }
};

// Regular grid layout of SDF samples: nodes of linspace(min[a], max[a], dims[a])
// along each axis a. Samples are stored with x fastest, then y, then z:
//   index = i + dims[0] * (j + dims[1] * k).
struct GridInfo {
  int dim = 3;                       // 2 or 3
  std::array<int, 3> dims{0, 0, 0};  // number of nodes per axis (dims[2] = 1 in 2D)
  std::array<double, 3> min{0, 0, 0};
  std::array<double, 3> max{0, 0, 0};
  std::int64_t NumNodes() const {
    return static_cast<std::int64_t>(dims[0]) * dims[1] * (dim == 3 ? dims[2] : 1);
  }
  double Spacing(int axis) const {
    return dims[axis] > 1 ? (max[axis] - min[axis]) / (dims[axis] - 1) : 0.0;
  }
};

// Signed-distance samples (p_i, s_i). `points` is N x dim (dim 2 or 3).
// `grid` is set when the samples are the nodes of a regular grid (in the
// order documented on GridInfo). `clamp` > 0 marks a clamped SDF: values with
// |s| >= clamp carry only the information "at least clamp away".
struct SdfSamples {
  int dim = 3;
  MatrixXd points;
  VectorXd values;
  std::optional<GridInfo> grid;
  double clamp = 0.0;
  // A pseudo-SDF (paper §5.3, Fig. 25): +1 / -1 when the values of that sign
  // are only lower bounds on the distance to the surface (|s| <= distance),
  // as for the inside of a swept volume or a CSG union computed by min():
  // such spheres are still empty of surface but need not touch it, so RFTA
  // uses them as constraints without tangency points. 0 = exact SDF.
  int bound_sign = 0;
  std::int64_t Size() const { return values.size(); }
};

// A set of closed (or open) 2D polylines: the 2D counterpart of Mesh. V holds
// the vertices with z = 0; each row of E is a directed edge (a, b). Closed
// curves are oriented counter-clockwise around the inside (the inside lies to
// the left of every edge), as mesh faces are wound outward.
struct Polyline {
  MatrixX3d V;
  Eigen::Matrix<int, Eigen::Dynamic, 2, Eigen::RowMajor> E;
  int NumVertices() const { return static_cast<int>(V.rows()); }
  int NumEdges() const { return static_cast<int>(E.rows()); }
  bool Empty() const { return E.rows() == 0; }
};

// Values on the nodes of a regular grid (layout and order of GridInfo): an
// occupancy or winding-number volume (voxelizers), a 2D/3D scalar field.
struct VolumeGrid {
  GridInfo info;
  VectorXd values;  // info.NumNodes() entries, x fastest
};

}  // namespace arcs
