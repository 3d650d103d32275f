// The third-party back-ends of the SDF -> mesh baselines, behind plain types
// (no CGAL / OpenVDB type here). Each lives in its own translation unit
// (sdfmesh/cgal/, sdfmesh/openvdb/) compiled into its own small static
// library, so the libraries' headers and flags (CGAL's -frounding-math) stay
// there. Built without the package, a function throws Error("... built
// without X: install libX-dev"). Callers (power_diagram.cpp, vdb_mesher.cpp)
// validate the input first.
#pragma once

#include "framework/types.h"

#include <array>
#include <cstdint>
#include <vector>

namespace arcs::sdfmesh_detail {

bool CgalAvailable();
bool OpenVdbAvailable();

// CGAL Regular_triangulation_3 of the points (rows of P, N x >= 3) with the
// given weights (squared radii; all zero = Delaunay). Returns the finite
// tetrahedra (sample indices) that have vertices both with and without
// inside[i] set; `num_vertices` receives the number of vertices of the
// triangulation (points hidden by the weights or duplicated are not),
// `num_tetrahedra` the number of finite tetrahedra, `dimension` its
// dimension (< 3: the points span no volume; no tetrahedra then).
std::vector<std::array<int, 4>> RegularTetrahedraCrossing(const MatrixXd& P, const VectorXd& weights,
                                                          const std::vector<std::uint8_t>& inside,
                                                          std::int64_t* num_vertices, std::int64_t* num_tetrahedra,
                                                          int* dimension);

// OpenVDB tools::volumeToMesh of the grid's values (a FloatGrid with every
// node an active voxel, positioned by the grid's scale and translation;
// `background` outside). Polygons as OpenVDB winds them.
void OpenVdbVolumeToMesh(const VectorXd& values, const GridInfo& grid, double background, double isovalue,
                         double adaptivity, bool relax_disoriented_triangles, MatrixX3d* V,
                         std::vector<std::array<int, 3>>* triangles, std::vector<std::array<int, 4>>* quads);

}  // namespace arcs::sdfmesh_detail
