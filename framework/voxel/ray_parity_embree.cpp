// Ray-parity occupancy with Embree 3 (see ray_parity.h). Compiled into
// arcs_voxel always; the Embree code only with ARCS_WITH_EMBREE (the CMake
// block after arcs_module(voxel ...) defines it and links `embree`).
#include "framework/voxel/ray_parity.h"

#include "framework/error.h"
#include "framework/spatial/topology.h"
#include "framework/util/parallel.h"
#include "framework/voxel/voxelize.h"

#ifdef ARCS_WITH_EMBREE
#include <embree3/rtcore.h>
#endif

#include <algorithm>
#include <cmath>
#include <vector>

namespace arcs {

#ifdef ARCS_WITH_EMBREE

bool HaveRayParity() { return true; }

VectorXd RayParityOccupancy(const Mesh& mesh_in, const GridInfo& g) {
  CheckMeshIndices(mesh_in, "RayParityOccupancy", /*finite=*/true);
  if (g.dim != 3) throw Error("RayParityOccupancy needs a 3D grid");
  const Mesh mesh = DropDegenerateFaces(mesh_in);
  VectorXd occ = VectorXd::Zero(g.NumNodes());
  if (mesh.NumFaces() == 0) return occ;
  RTCDevice device = rtcNewDevice(nullptr);
  if (!device) throw Error("Embree: rtcNewDevice failed");
  RTCScene scene = rtcNewScene(device);
  rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
  RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                         3 * sizeof(float), mesh.NumVertices()));
  auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                            3 * sizeof(unsigned), mesh.NumFaces()));
  double zlo = g.min[2];
  for (int v = 0; v < mesh.NumVertices(); ++v) {
    for (int c = 0; c < 3; ++c) vb[3 * v + c] = static_cast<float>(mesh.V(v, c));
    zlo = std::min(zlo, mesh.V(v, 2));
  }
  for (int f = 0; f < mesh.NumFaces(); ++f)
    for (int c = 0; c < 3; ++c) ib[3 * f + c] = static_cast<unsigned>(mesh.F(f, c));
  rtcCommitGeometry(geom);
  rtcAttachGeometry(scene, geom);
  rtcReleaseGeometry(geom);
  rtcCommitScene(scene);

  const int nx = g.dims[0], ny = g.dims[1], nz = g.dims[2];
  const double scale = std::max({g.max[0] - g.min[0], g.max[1] - g.min[1], g.max[2] - g.min[2], 1e-30});
  const float z0 = static_cast<float>(zlo - 0.1 * scale - 1.0);
  const float step = static_cast<float>(1e-6 * scale);
  ParallelFor(
      static_cast<std::int64_t>(nx) * ny,
      [&](std::int64_t b, std::int64_t e) {
        RTCIntersectContext context;
        std::vector<float> hits;
        for (std::int64_t col = b; col < e; ++col) {
          const int i = static_cast<int>(col % nx), j = static_cast<int>(col / nx);
          hits.clear();
          float tnear = 0.0f;
          for (int guard = 0; guard < 100000; ++guard) {
            rtcInitIntersectContext(&context);
            RTCRayHit rh{};
            rh.ray.org_x = static_cast<float>(GridCoord(g, 0, i));
            rh.ray.org_y = static_cast<float>(GridCoord(g, 1, j));
            rh.ray.org_z = z0;
            rh.ray.dir_x = 0.0f, rh.ray.dir_y = 0.0f, rh.ray.dir_z = 1.0f;
            rh.ray.tnear = tnear;
            rh.ray.tfar = INFINITY;
            rh.ray.mask = 0xFFFFFFFFu;
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(scene, &context, &rh);
            if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) break;
            hits.push_back(z0 + rh.ray.tfar);
            tnear = rh.ray.tfar + step;
          }
          // Node k is inside when an odd number of hits lie above it.
          std::size_t h = 0;  // hits at or below the node
          for (int k = 0; k < nz; ++k) {
            const double z = GridCoord(g, 2, k);
            while (h < hits.size() && hits[h] <= z) ++h;
            occ[i + static_cast<std::int64_t>(nx) * (j + static_cast<std::int64_t>(ny) * k)] =
                ((hits.size() - h) & 1) ? 1.0 : 0.0;
          }
        }
      },
      16);
  rtcReleaseScene(scene);
  rtcReleaseDevice(device);
  return occ;
}

#else

bool HaveRayParity() { return false; }

VectorXd RayParityOccupancy(const Mesh&, const GridInfo&) {
  throw Error("method ray_parity needs Embree 3: this build of arcs was configured without it "
              "(install libembree-dev and re-run cmake)");
}

#endif

}  // namespace arcs
