// The dual-contouring machinery shared by DualContouring and DCSDD
// (framework/sdfmesh/dcsdd.cpp): the sign-changing edges with their Hermite
// data, the active cells with their vertices, the quads, the QEF solve.
// Internal: not part of the public API.
#pragma once

#include "framework/types.h"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <vector>

namespace arcs::dc_detail {

// A sign-changing grid edge from `node` along `axis` (GridInfo node index).
struct HermiteEdge {
  std::int64_t node = 0;
  int axis = 0;
  bool inside_low = false;  // the node at `node` is inside (value < isovalue)
  Vec3 p = Vec3::Zero();    // crossing point
  Vec3 n = Vec3::Zero();    // per-edge unit normal (zero when the gradient vanishes)
};

// A dual vertex: one sheet of one active cell.
struct DcVertex {
  std::int64_t cell = 0;               // linear cell index (i + (nx-1)(j + (ny-1)k))
  std::vector<int> edges;              // HermiteEdge ids of the sheet
  std::vector<signed char> cube_edge;  // the cube-edge number (0..11) of each, in the cell
};

struct DcGrid {
  GridInfo grid;
  std::array<int, 3> cells{0, 0, 0};       // cells per axis (dims - 1)
  std::array<std::vector<double>, 3> coords;  // node coordinates per axis
  std::vector<HermiteEdge> edges;
  std::vector<DcVertex> vertices;
  // Quads: four vertex ids, wound outward, and the Hermite edge each crosses.
  std::vector<std::array<int, 4>> quads;
  std::vector<int> quad_edge;
  int multi_sheet_cells = 0;

  Vec3 CellMin(std::int64_t cell) const;
  Vec3 CellMax(std::int64_t cell) const;
  Vec3 Spacing() const;
  // The cell containing x (clamped to the grid).
  std::int64_t CellOf(const Vec3& x) const;
};

// Finds the Hermite points and per-edge normals (Normals::kEdge), the cells'
// vertices (one per cell, or one per MC sheet with `manifold`) and the quads.
// Vertex positions are not computed here.
DcGrid BuildDcGrid(const VectorXd& values, const GridInfo& grid, double isovalue, bool manifold);

// Gradient of the trilinear interpolant of `cell` at x (x may lie on the
// cell's boundary).
Vec3 TrilinearGradient(const VectorXd& values, const DcGrid& g, std::int64_t cell, const Vec3& x);

// Normal equations of a small least-squares problem in x (3 unknowns).
struct Normal3 {
  Eigen::Matrix3d AtA = Eigen::Matrix3d::Zero();
  Vec3 Atb = Vec3::Zero();
  void AddRow(const Vec3& a, double b, double weight = 1.0) {
    AtA += weight * weight * a * a.transpose();
    Atb += weight * weight * b * a;
  }
};

// argmin of |A x - b|^2 by the truncated pseudo-inverse about `center`:
// x = center + pinv(AtA) (Atb - AtA center), dropping singular values of A
// below `threshold` times the largest. No rows: `center`.
Vec3 SolveAbout(const Normal3& q, const Vec3& center, double threshold);

// The QEF vertex of every DcVertex (DualContouring's placement). `normals`
// and the thresholds as DualContouringOptions; `clamped` (optional) flags the
// vertices moved onto their cell.
MatrixX3d PlaceDcVertices(const VectorXd& values, const DcGrid& g, bool trilinear_normals, double svd_threshold,
                          bool clamp_to_cell, std::vector<std::uint8_t>* clamped = nullptr);

// Clamps x onto the box [lo, hi]; returns whether it moved.
bool ClampToBox(Vec3* x, const Vec3& lo, const Vec3& hi);

// Triangles of the quads (each split along its shorter diagonal), wound as
// the quads.
MatrixX3i TriangulateQuads(const std::vector<std::array<int, 4>>& quads, const MatrixX3d& V);

// The mesh without the vertices no face uses (a cell whose only crossed edges
// lie on the grid boundary has a vertex but no quad), order kept.
Mesh CompactMesh(MatrixX3d V, MatrixX3i F);

}  // namespace arcs::dc_detail
