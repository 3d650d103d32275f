// Point-cloud -> mesh reconstructors besides screened Poisson
// (framework/reconstruct/poisson.h): the alternatives of RFTA Fig. 26 and of
// the graph-Voronoi comparison. All take a PointCloud in any frame and return
// a mesh in the same frame, faces wound outward (CCW seen from outside) where
// an outside is defined, unused input points dropped from the vertices.
//
// Common input rules (PrepareReconstructionInput, point_utils.h): fewer than
// 4 points, a non-finite coordinate, or (ball pivoting) missing / zero /
// non-finite normals -> Error naming the method and the row. Exact duplicate
// positions are merged (counted in the report). No outlier removal: an
// outlier becomes part of the surface or a separate piece (documented in
// docs/point_reconstructors.md). An empty result -> Error.
//
// Normals: ball pivoting needs them and errors when absent (the pipeline
// must say how they were made: add the `estimate_normals` point_modifier);
// alpha shapes ignore them; advancing front uses them, when present, only to
// orient open pieces.
//
// Back-ends (docs/point_reconstructors.md has the measured compile times):
// CGAL (alpha shapes, advancing front), Open3D (ball pivoting), each in its
// own translation unit. Built without one, its function throws
// Error("built without X: install libX-dev").
#pragma once

#include "framework/context.h"
#include "framework/types.h"

namespace arcs {

// What a reconstructor did, for the results table.
struct PointReconstructionReport {
  int points_used = 0;          // after removing duplicates
  int duplicates_removed = 0;
  double spacing = 0.0;         // PointSpacing of the cleaned points
  double radius = 0.0;          // the (smallest) ball / alpha radius used; 0 if none
  int flipped_components = 0;   // components re-oriented by OrientComponents
};

// Ball pivoting (Bernardini et al. 1999) via Open3D: a ball of radius r rolls
// over the points, every triangle whose circumscribed r-ball is empty of
// other points and touches three points becomes a face; passes with larger
// radii fill what a smaller ball fell through. Faces are oriented by the
// point normals. Not guaranteed closed: holes remain wherever the sampling is
// sparser than the largest ball.
struct BallPivotingOptions {
  // Smallest ball radius; 0 = automatic: radius_factor * PointSpacing.
  double radius = 0.0;
  // Automatic radius in units of the point spacing h (mean nearest-neighbour
  // distance). Measured on 2k / 4k / 20k area-uniform samples of a sphere and
  // a torus (docs/point_reconstructors.md): with three radii, 3 h leaves
  // 0-78 boundary edges (a few tiny holes) and no non-manifold vertex; 1.5 h
  // leaves 12-668 boundary edges and up to 56 non-manifold vertices: random
  // sampling has gaps several spacings wide. Range [0.1, 100].
  double radius_factor = 3.0;
  // Number of radii: r, 2r, 4r, ... (Bernardini et al. pass with increasing
  // radii). Range 1..8.
  int levels = 3;
  void Check() const;
};
Mesh ReconstructBallPivoting(const PointCloud& points, const BallPivotingOptions& options, const Context& ctx,
                             PointReconstructionReport* report = nullptr);

// Alpha shape (Edelsbrunner & Mücke 1994) via CGAL Alpha_shape_3 in
// REGULARIZED mode: the boundary of the union of the Delaunay tetrahedra
// whose circumsphere radius is at most alpha (plus the faces they need),
// wound outward from the solid. Closed by construction (every boundary facet
// separates interior from exterior), but may be non-manifold at pinched
// vertices/edges and encloses internal voids when alpha is too small for
// the interior tetrahedra (see `rule`), and fills concavities and holes
// narrower than alpha (it cannot resolve features smaller than the largest
// interior tetrahedron of the shape).
struct AlphaShapeOptions {
  // Alpha as a radius (CGAL's alpha is its square); 0 = automatic (rule).
  double radius = 0.0;
  // Automatic radius = radius_factor * base, where the base is
  //  "optimal": the radius of CGAL's find_optimal_alpha(1), the smallest
  //    alpha whose solid is one component containing every point. It sits
  //    exactly at the size of the largest interior Delaunay tetrahedra, so
  //    the solid still has voids and pinches there: measured on 2k / 4k /
  //    20k samples of a sphere and a torus, factor 1.0 gives 96-1745
  //    non-manifold edges and twice the area, 1.1-1.3 a closed manifold of
  //    the right genus every time (docs/point_reconstructors.md);
  //  "spacing": PointSpacing (the first idea). The Delaunay
  //    tetrahedra inside a surface sample have circumradii of the order of the
  //    local feature size (a sphere's radius, a tube's radius), not of the
  //    spacing, so a few spacings give only sliver shells (measured: 2.5 h on
  //    a sphere: 93 pieces, 4 % of the area); it needs a factor near
  //    feature size / spacing, different for every shape.
  std::string rule = "optimal";
  // Range [0.1, 1000].
  double radius_factor = 1.2;
  void Check() const;
};
Mesh ReconstructAlphaShape(const PointCloud& points, const AlphaShapeOptions& options, const Context& ctx,
                           PointReconstructionReport* report = nullptr);

// Advancing front surface reconstruction (Cohen-Steiner & Da 2004) via CGAL:
// grows an orientable manifold surface from the Delaunay triangulation's
// facets, by a plausibility priority (dihedral angle, radius ratio). Output:
// a manifold, consistently oriented surface; closed components get positive
// volume, open ones follow the normals when present. Parameters are CGAL's.
struct AdvancingFrontOptions {
  // Candidate facets whose radius exceeds this multiple of the neighbouring
  // facets' are rejected (CGAL default 5). Range [1, 1000].
  double radius_ratio_bound = 5.0;
  // Angle bound for sliver facets (radians, CGAL default 0.52 ~ 30 degrees).
  // Range [0, pi/2].
  double beta = 0.52;
  void Check() const;
};
Mesh ReconstructAdvancingFront(const PointCloud& points, const AdvancingFrontOptions& options, const Context& ctx,
                               PointReconstructionReport* report = nullptr);

// Back-end availability (false when built without the package).
bool CgalReconstructorsAvailable();
bool BallPivotingAvailable();

}  // namespace arcs
