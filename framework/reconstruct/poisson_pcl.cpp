// The only translation unit that sees PCL. It includes pcl/surface/poisson.h
// (declarations) and links libpcl_surface's explicit instantiation for
// pcl::PointNormal; never impl/poisson.hpp, which takes ~46 s to compile.
#include "framework/util/stdout_silencer.h"
#include "framework/reconstruct/poisson_pcl.h"

#include <fcntl.h>
#include <unistd.h>

#include <cstdio>

#include "framework/error.h"

#include <algorithm>
#include <string>

#ifdef ARCS_WITH_PCL
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/surface/poisson.h>

#include <exception>
#include <mutex>
#endif


namespace arcs::poisson_detail {

#ifdef ARCS_WITH_PCL

bool PclAvailable() { return true; }

Mesh RunPclPoisson(const std::vector<float>& xyz, const std::vector<float>& normals,
                   const PoissonOptions& o, int depth) {
  // pcl::Poisson keeps its octree nodes in a process-wide static allocator
  // (OctNode::internalAllocator, reset at the start of every run) and sets
  // the global TreeNodeData::UseIndex: two concurrent runs would corrupt each
  // other, so runs are serialised.
  static std::mutex mutex;
  std::lock_guard<std::mutex> lock(mutex);

  const std::size_t n = xyz.size() / 3;
  auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointNormal>>();
  cloud->resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    pcl::PointNormal& p = (*cloud)[i];
    p.x = xyz[3 * i];
    p.y = xyz[3 * i + 1];
    p.z = xyz[3 * i + 2];
    p.normal_x = normals[3 * i];
    p.normal_y = normals[3 * i + 1];
    p.normal_z = normals[3 * i + 2];
    p.curvature = 0.0f;
  }

  pcl::Poisson<pcl::PointNormal> poisson;
  const int min_depth = std::min(o.min_depth, depth);
  poisson.setDepth(depth);
  poisson.setMinDepth(min_depth);
  poisson.setPointWeight(static_cast<float>(o.point_weight));
  poisson.setScale(static_cast<float>(o.scale));
  poisson.setSamplesPerNode(static_cast<float>(o.samples_per_node));
  // Quadratic B-splines: the only degree PCL's port runs (1 segfaults,
  // 3-5 throw "B-spline up-sampling not supported").
  poisson.setDegree(2);
  poisson.setManifold(o.manifold);
  poisson.setConfidence(false);       // normals are unit: every point weighs 1
  poisson.setOutputPolygons(false);   // triangles
  // Block Gauss-Seidel / block iso-extraction from depth 8 (PCL's default);
  // PCL warns on stderr and clamps when these are below min_depth.
  poisson.setSolverDivide(std::max(8, min_depth));
  poisson.setIsoDivide(std::max(8, min_depth));
  poisson.setThreads(o.threads);
  poisson.setInputCloud(cloud);

  pcl::PointCloud<pcl::PointNormal> out_points;
  std::vector<pcl::Vertices> polygons;
  try {
    // performReconstruction directly: reconstruct() would also build a
    // kd-tree over the input that Poisson never uses.
    // PCL's PoissonRecon port prints diagnostics ("Vertex pair not in list")
    // with printf; stdout belongs to arcs' own results, so it is silenced for
    // the call (calls are serialised by the lock above; arcs writes nothing to
    // stdout from other threads meanwhile).
    StdoutSilencer silence;
    poisson.performReconstruction(out_points, polygons);
  } catch (const std::exception& e) {
    throw Error(std::string("screened Poisson: PCL failed: ") + e.what());
  }

  Mesh mesh;
  const std::size_t nv = out_points.size();
  mesh.V.resize(static_cast<Eigen::Index>(nv), 3);
  for (std::size_t i = 0; i < nv; ++i) {
    mesh.V(static_cast<Eigen::Index>(i), 0) = out_points[i].x;
    mesh.V(static_cast<Eigen::Index>(i), 1) = out_points[i].y;
    mesh.V(static_cast<Eigen::Index>(i), 2) = out_points[i].z;
  }
  std::size_t nf = 0;
  for (const pcl::Vertices& poly : polygons) {
    if (poly.vertices.size() >= 3) nf += poly.vertices.size() - 2;
  }
  mesh.F.resize(static_cast<Eigen::Index>(nf), 3);
  Eigen::Index f = 0;
  for (const pcl::Vertices& poly : polygons) {
    const auto& v = poly.vertices;
    for (std::size_t k = 0; k < v.size(); ++k) {
      if (v[k] < 0 || static_cast<std::size_t>(v[k]) >= nv) {
        throw Error("screened Poisson: PCL returned a face with vertex index " +
                    std::to_string(v[k]) + " >= " + std::to_string(nv) + " vertices");
      }
    }
    for (std::size_t k = 2; k < v.size(); ++k) {  // fan (only if PCL ever returns polygons)
      mesh.F(f, 0) = static_cast<int>(v[0]);
      mesh.F(f, 1) = static_cast<int>(v[k - 1]);
      mesh.F(f, 2) = static_cast<int>(v[k]);
      ++f;
    }
  }
  return mesh;
}

#else  // !ARCS_WITH_PCL

bool PclAvailable() { return false; }

Mesh RunPclPoisson(const std::vector<float>&, const std::vector<float>&, const PoissonOptions&,
                   int) {
  throw Error("screened Poisson needs PCL: install libpcl-dev");
}

#endif

}  // namespace arcs::poisson_detail
