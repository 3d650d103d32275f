// The Open3D screened-Poisson back-end (see framework/reconstruct/poisson_open3d.h).
// Lives with the other Open3D translation unit so Open3D's headers stay here.
#include "framework/util/stdout_silencer.h"
#include "framework/reconstruct/poisson_open3d.h"

#include "framework/error.h"

#include <string>

#ifdef ARCS_WITH_OPEN3D
#include <open3d/geometry/PointCloud.h>
#include <open3d/geometry/TriangleMesh.h>
#include <open3d/utility/Logging.h>

#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <exception>
#include <mutex>
#endif

namespace arcs::poisson_detail {

#ifdef ARCS_WITH_OPEN3D

bool Open3dPoissonAvailable() { return true; }


Open3dPoissonResult RunOpen3dPoisson(const std::vector<double>& xyz, const std::vector<double>& normals, int depth,
                                     double scale, int threads, bool capture_area) {
  static std::mutex mutex;
  std::lock_guard<std::mutex> lock(mutex);
  const std::size_t n = xyz.size() / 3;
  open3d::geometry::PointCloud pcd;
  pcd.points_.resize(n);
  pcd.normals_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    pcd.points_[i] = Eigen::Vector3d(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
    pcd.normals_[i] = Eigen::Vector3d(normals[3 * i], normals[3 * i + 1], normals[3 * i + 2]);
  }
  Open3dPoissonResult out;
  auto& logger = open3d::utility::Logger::GetInstance();
  const auto level = open3d::utility::GetVerbosityLevel();
  // Open3D logs through its own logger (stdout by default); arcs' stdout carries results.
  logger.SetPrintFunction([&out, capture_area](const std::string& line) {
    if (!capture_area) return;
    const auto at = line.find("Point weight / Estimated Area:");
    if (at == std::string::npos) return;
    double w = 0, a = 0;
    if (std::sscanf(line.c_str() + at + 30, "%lf / %lf", &w, &a) == 2) {
      out.point_weight_sum = w;
      out.estimated_area = a;
    }
  });
  open3d::utility::SetVerbosityLevel(capture_area ? open3d::utility::VerbosityLevel::Debug
                                                  : open3d::utility::VerbosityLevel::Error);
  std::shared_ptr<open3d::geometry::TriangleMesh> tm;
  std::string err;
  try {
    StdoutSilencer silence;
    tm = std::get<0>(open3d::geometry::TriangleMesh::CreateFromPointCloudPoisson(
        pcd, static_cast<std::size_t>(depth), 0.0f, static_cast<float>(scale), false, threads));
  } catch (const std::exception& e) {
    err = e.what();
  }
  logger.ResetPrintFunction();
  open3d::utility::SetVerbosityLevel(level);
  if (!err.empty()) throw Error("screened Poisson: Open3D failed: " + err);
  if (!tm) throw Error("screened Poisson: Open3D returned no mesh");
  out.mesh.V.resize(static_cast<Eigen::Index>(tm->vertices_.size()), 3);
  for (std::size_t i = 0; i < tm->vertices_.size(); ++i) out.mesh.V.row(static_cast<Eigen::Index>(i)) = tm->vertices_[i].transpose();
  out.mesh.F.resize(static_cast<Eigen::Index>(tm->triangles_.size()), 3);
  for (std::size_t f = 0; f < tm->triangles_.size(); ++f)
    for (int k = 0; k < 3; ++k) out.mesh.F(static_cast<Eigen::Index>(f), k) = tm->triangles_[f](k);
  return out;
}

#else

bool Open3dPoissonAvailable() { return false; }

Open3dPoissonResult RunOpen3dPoisson(const std::vector<double>&, const std::vector<double>&, int, double, int, bool) {
  throw Error("screened Poisson: arcs was built without Open3D: install libopen3d-dev and reconfigure (ARCS_WITH_OPEN3D)");
}

#endif

}  // namespace arcs::poisson_detail
