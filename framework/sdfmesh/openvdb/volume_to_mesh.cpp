// The only translation unit that sees OpenVDB.
#include "framework/error.h"
#include "framework/sdfmesh/backends.h"

#ifdef ARCS_WITH_OPENVDB
#include <openvdb/openvdb.h>
#include <openvdb/tools/VolumeToMesh.h>
#endif

namespace arcs::sdfmesh_detail {

#ifdef ARCS_WITH_OPENVDB

bool OpenVdbAvailable() { return true; }

void OpenVdbVolumeToMesh(const VectorXd& values, const GridInfo& grid, double background, double isovalue,
                         double adaptivity, bool relax, MatrixX3d* V, std::vector<std::array<int, 3>>* triangles,
                         std::vector<std::array<int, 4>>* quads) {
  openvdb::initialize();  // idempotent
  const int nx = grid.dims[0], ny = grid.dims[1], nz = grid.dims[2];
  openvdb::FloatGrid::Ptr vdb = openvdb::FloatGrid::create(static_cast<float>(background));
  {
    openvdb::FloatGrid::Accessor acc = vdb->getAccessor();
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
          acc.setValue(openvdb::Coord(i, j, k),
                       static_cast<float>(values[i + static_cast<std::int64_t>(nx) * (j + static_cast<std::int64_t>(ny) * k)]));
  }
  const openvdb::math::Vec3d scale(grid.Spacing(0), grid.Spacing(1), grid.Spacing(2));
  const openvdb::math::Vec3d origin(grid.min[0], grid.min[1], grid.min[2]);
  vdb->setTransform(openvdb::math::Transform::Ptr(new openvdb::math::Transform(
      openvdb::math::MapBase::Ptr(new openvdb::math::ScaleTranslateMap(scale, origin)))));
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> tris;
  std::vector<openvdb::Vec4I> qs;
  openvdb::tools::volumeToMesh(*vdb, points, tris, qs, isovalue, adaptivity, relax);
  V->resize(static_cast<Eigen::Index>(points.size()), 3);
  for (size_t i = 0; i < points.size(); ++i) V->row(i) << points[i][0], points[i][1], points[i][2];
  triangles->clear();
  for (const auto& t : tris) triangles->push_back({static_cast<int>(t[0]), static_cast<int>(t[1]), static_cast<int>(t[2])});
  quads->clear();
  for (const auto& q : qs)
    quads->push_back({static_cast<int>(q[0]), static_cast<int>(q[1]), static_cast<int>(q[2]), static_cast<int>(q[3])});
}

#else

bool OpenVdbAvailable() { return false; }

void OpenVdbVolumeToMesh(const VectorXd&, const GridInfo&, double, double, double, bool, MatrixX3d*,
                         std::vector<std::array<int, 3>>*, std::vector<std::array<int, 4>>*) {
  throw Error("vdb_mesher: arcs was built without OpenVDB: install libopenvdb-dev and rebuild (ARCS_WITH_OPENVDB)");
}

#endif

}  // namespace arcs::sdfmesh_detail
