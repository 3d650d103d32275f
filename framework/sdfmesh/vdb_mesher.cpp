#include "framework/sdfmesh/vdb_mesher.h"

#include "framework/error.h"
#include "framework/sdfmesh/backends.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace arcs {

bool VdbMesherAvailable() { return sdfmesh_detail::OpenVdbAvailable(); }

void VdbMesherOptions::Check() const {
  if (!std::isfinite(isovalue)) throw OptionError("isovalue = " + std::to_string(isovalue) + ": must be finite");
  ARCS_CHECK_OPTION(adaptivity >= 0.0 && adaptivity <= 1.0, "adaptivity", adaptivity, "in [0, 1]");
}

Mesh VdbVolumeToMesh(const VectorXd& values, const GridInfo& grid, const VdbMesherOptions& o) {
  o.Check();
  if (grid.dim != 3) throw Error("vdb_mesher: the grid must be 3D (grid.dim = " + std::to_string(grid.dim) + ")");
  for (int a = 0; a < 3; ++a)
    if (grid.dims[a] < 2 || !(grid.max[a] > grid.min[a]))
      throw Error("vdb_mesher: the grid needs at least 2 nodes and a positive extent along axis " + std::to_string(a));
  if (grid.NumNodes() != values.size())
    throw Error("vdb_mesher: the grid has " + std::to_string(grid.NumNodes()) + " nodes but there are " +
                std::to_string(values.size()) + " values");
  if (!values.allFinite()) throw Error("vdb_mesher: the values must be finite");
  // Outside the grid: far outside (above every value), so a surface that
  // reaches the grid's boundary is closed there.
  const double background = std::max(values.maxCoeff(), o.isovalue) + 1.0;
  Mesh m;
  std::vector<std::array<int, 3>> tris;
  std::vector<std::array<int, 4>> quads;
  sdfmesh_detail::OpenVdbVolumeToMesh(values, grid, background, o.isovalue, o.adaptivity,
                                      o.relax_disoriented_triangles, &m.V, &tris, &quads);
  if (tris.empty() && quads.empty()) throw Error("vdb_mesher: OpenVDB's volumeToMesh produced no polygons");
  // OpenVDB winds its polygons counter-clockwise seen from the outside
  // (larger values), as arcs does (checked by the tests through the volume
  // sign); quads split along the shorter diagonal.
  m.F.resize(static_cast<Eigen::Index>(tris.size() + 2 * quads.size()), 3);
  Eigen::Index f = 0;
  for (const auto& t : tris) m.F.row(f++) << t[0], t[1], t[2];
  for (const auto& q : quads) {
    const int a = q[0], b = q[1], c = q[2], d = q[3];
    if ((m.V.row(a) - m.V.row(c)).squaredNorm() <= (m.V.row(b) - m.V.row(d)).squaredNorm()) {
      m.F.row(f++) << a, b, c;
      m.F.row(f++) << a, c, d;
    } else {
      m.F.row(f++) << a, b, d;
      m.F.row(f++) << b, c, d;
    }
  }
  return m;
}

}  // namespace arcs
