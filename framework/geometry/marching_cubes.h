// Marching cubes (3D) and marching squares (2D) on regular grids of samples.
//
// This is the paper's "MC" baseline: standard marching cubes with one vertex
// per sign-changing grid edge, placed by linear interpolation of the two
// node values (as libigl's igl::marching_cubes). The case table is not the
// classic Lorensen–Cline/Bourke table: it is derived at start-up (see
// marching_cubes.cpp) from a fixed face rule, which makes the output
// watertight by construction:
//  * a node is "inside" iff value < isovalue; a value exactly equal to the
//    isovalue counts as outside (the paper's convention S = 0 -> positive);
//  * on a face with alternating corner signs (the ambiguous face) the inside
//    corners are separated (outside connected across the diagonal); the
//    choice depends only on the face's own corners, so both cubes sharing a
//    face agree and every crossed grid edge gets exactly one vertex;
//  * triangles are oriented with normals pointing to the outside (positive)
//    side: for a negative-inside SDF, counter-clockwise seen from outside.
// Consequences: a sign field whose zero set does not touch the grid boundary
// gives a closed, edge- and vertex-manifold, consistently oriented mesh. A
// vertex interpolated exactly onto a node (value == isovalue) may coincide in
// position with another vertex; such meshes are topologically sound but can
// contain zero-area triangles.
#pragma once

#include "framework/types.h"

#include <Eigen/Core>

#include <array>
#include <vector>

namespace arcs {

// `values` are the grid's node values in GridInfo order (x fastest);
// grid.dim == 3, every dims[a] >= 2, values finite. Deterministic and
// independent of the thread count (parallel over z-slabs, merged in order).
// Vertices are ordered by their grid edge (z-layer, then y, then x, then
// axis); faces by cube (z, y, x).
Mesh MarchingCubes(const VectorXd& values, const GridInfo& grid, double isovalue = 0.0);

// Closed polylines in the plane: V is n x 2, E is m x 2 directed edges
// (E(i,0) -> E(i,1)).
struct Polyline2 {
  MatrixXd V;
  Eigen::MatrixX2i E;
};

// Marching squares on a 2D grid (grid.dim == 2, values index i + dims[0]*j).
// Same conventions as MarchingCubes: inside iff value < isovalue, saddle
// cells separate their inside corners, one vertex per crossed grid edge.
// Edges are oriented with the inside on the left, so an outer boundary runs
// counter-clockwise and a hole's boundary clockwise.
Polyline2 MarchingSquares(const VectorXd& values, const GridInfo& grid, double isovalue = 0.0);

namespace detail {
// Cube corner c has offset (c & 1, (c >> 1) & 1, (c >> 2) & 1). Cube edge e
// runs along axis e / 4 from corner MarchingCubesEdgeCorner(e).
int MarchingCubesEdgeCorner(int edge);
// Triangles (3 cube-edge indices each, oriented) of sign configuration
// `config` (bit c set = corner c inside).
const std::vector<std::array<int, 3>>& MarchingCubesCase(int config);
}  // namespace detail

}  // namespace arcs
