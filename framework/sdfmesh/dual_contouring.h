// Dual contouring (Ju, Losasso, Schaefer, Warren, SIGGRAPH 2002) of SDF
// values on a regular grid: the standard grid baseline that keeps sharp
// features marching cubes rounds off.
//
// Conventions (those of MarchingCubes, framework/geometry/marching_cubes.h):
// a node is inside iff value < isovalue; faces are wound outward (towards the
// positive side).
//  * Hermite data: on every grid edge whose ends have opposite signs, the
//    point where the linear interpolation of the two values reaches the
//    isovalue, with a normal: the normalised gradient of the trilinear
//    interpolant of the cell whose vertex is being placed, at that point
//    (Normals::kTrilinear), or one normal per edge, the gradient of the
//    trilinear interpolants averaged over the cells around the edge (= the
//    exact difference along the edge and central differences across it,
//    Normals::kEdge).
//  * One vertex per cell with a sign change (or, with `manifold`, one per
//    sheet of the cell: the connected patches of marching cubes' case table,
//    which share its face rule, so the result has MC's topology; "dual
//    marching cubes"). One exception: where one sheet of a cell meets both
//    segments of an ambiguous face (MC's tunnel configurations), the two
//    sheets on either side are joined by one edge with four faces. The vertex minimises the QEF
//    sum_i (n_i . (x - p_i))^2 over its edges, solved by the truncated-SVD
//    pseudo-inverse about the mass point (the mean of the p_i): singular
//    values below svd_threshold times the largest are dropped, so flat and
//    edge-like cells fall back towards the mass point along the free
//    directions. Optionally clamped onto the cell.
//  * One quad per sign-changing interior edge, joining the vertices of the
//    four cells around it, oriented by the sign; each quad is split into two
//    triangles along its shorter diagonal. Edges on the grid boundary have
//    fewer than four cells and make no quad (the surface is open there).
#pragma once

#include "framework/types.h"
#include "framework/util/enum_names.h"

#include <cstdint>

namespace arcs {

struct DualContouringOptions {
  enum class Normals { kTrilinear, kEdge };
  double isovalue = 0.0;              // level extracted (inside iff value < isovalue)
  double svd_threshold = 0.1;         // QEF: drop singular values < svd_threshold * largest (Ju et al. truncate at 0.1), in [0, 1)
  // One normal per edge (the cells' trilinear gradients averaged), or each cell's own trilinear gradient.
  // kEdge measured better: mean Hausdorff on fandisk, rocker_arm, joint, couplingdown 0.114 / 0.038 at
  // n = 20 / 40 against 0.130 / 0.050 with kTrilinear (MC: 0.127 / 0.055).
  Normals normals = Normals::kEdge;
  bool clamp_to_cell = true;          // move a vertex the QEF puts outside its cell onto the cell's box
  bool manifold = false;              // one vertex per MC sheet in a cell (manifold output) instead of one per cell
  void Check() const;
};
// The stage's `normals` names, in its choice order.
inline constexpr EnumName<DualContouringOptions::Normals> kDcNormalsNames[] = {
    {DualContouringOptions::Normals::kEdge, "edge"}, {DualContouringOptions::Normals::kTrilinear, "trilinear"}};

struct DualContouringStats {
  int vertices = 0;
  int quads = 0;
  int clamped = 0;            // vertices moved onto their cell's box
  int multi_sheet_cells = 0;  // cells with more than one MC sheet (non-manifold candidates without `manifold`)
};

// `values` in GridInfo order (x fastest), grid.dim == 3, dims >= 2 on every
// axis, values finite (throws arcs::Error otherwise). Deterministic at any
// thread count; vertices ordered by cell (z, y, x), then sheet.
Mesh DualContouring(const VectorXd& values, const GridInfo& grid, const DualContouringOptions& options = {},
                    DualContouringStats* stats = nullptr);

}  // namespace arcs
