// A 2D Delaunay triangulation behind a plain interface (CGAL's
// Delaunay_triangulation_2 with exact predicates; the only CGAL type is in
// points/cgal/delaunay_2d.cpp). Used by graph_voronoi's full-resolution
// refinement to triangulate each coarse face's points in its own plane.
#pragma once

#include <array>
#include <vector>

namespace arcs::points_detail {

// Delaunay triangles of the points (x[i], y[i]), counter-clockwise, as
// indices into the input. Points at bit-identical positions are one vertex:
// the first of them is used and `merged` (optional) counts the others.
// Collinear or fewer than three distinct points give no triangles. Throws
// Error when arcs was built without CGAL.
std::vector<std::array<int, 3>> Delaunay2D(const std::vector<double>& x, const std::vector<double>& y,
                                           int* merged = nullptr);

}  // namespace arcs::points_detail
