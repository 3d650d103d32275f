// The only translation unit that sees Open3D.
#include "framework/points/backends.h"

#include "framework/error.h"

#ifdef ARCS_WITH_OPEN3D
#include <open3d/geometry/PointCloud.h>
#include <open3d/geometry/TriangleMesh.h>
#include <open3d/utility/Logging.h>

#include <exception>
#include <string>
#endif

namespace arcs::points_detail {

#ifdef ARCS_WITH_OPEN3D

bool Open3dAvailable() { return true; }

Mesh Open3dBallPivoting(const MatrixX3d& P, const MatrixX3d& N, const std::vector<double>& radii) {
  // Open3D logs through its own logger (stdout); arcs' stdout carries results.
  open3d::utility::SetVerbosityLevel(open3d::utility::VerbosityLevel::Error);
  open3d::geometry::PointCloud pcd;
  pcd.points_.resize(P.rows());
  pcd.normals_.resize(P.rows());
  for (int i = 0; i < P.rows(); ++i) {
    pcd.points_[i] = P.row(i).transpose();
    pcd.normals_[i] = N.row(i).transpose();
  }
  std::shared_ptr<open3d::geometry::TriangleMesh> tm;
  try {
    tm = open3d::geometry::TriangleMesh::CreateFromPointCloudBallPivoting(pcd, radii);
  } catch (const std::exception& e) {
    throw Error(std::string("ball_pivoting: Open3D failed: ") + e.what());
  }
  Mesh m;
  m.V = P;  // Open3D keeps the input points as vertices, in order
  if (!tm || static_cast<long>(tm->vertices_.size()) != P.rows())
    throw Error("ball_pivoting: Open3D returned an unexpected vertex set");
  m.F.resize(static_cast<int>(tm->triangles_.size()), 3);
  for (int f = 0; f < m.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) m.F(f, k) = tm->triangles_[f](k);
  return m;
}

#else

bool Open3dAvailable() { return false; }

Mesh Open3dBallPivoting(const MatrixX3d&, const MatrixX3d&, const std::vector<double>&) {
  throw Error("ball_pivoting: arcs was built without Open3D: install libopen3d-dev and reconfigure (ARCS_WITH_OPEN3D)");
}

#endif

}  // namespace arcs::points_detail
