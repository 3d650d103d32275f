// Graph Voronoi at full resolution (beyond the paper): every point that is
// not a site is brought into the coarse surface, so the output keeps the
// coarse mesh's topology at the scan's resolution. The paper (§5) leaves
// "incorporating the pruned points" as future work and names weighted
// Delaunay triangulations; CoCone, its comparison, keeps every point.
//
// Method (a restricted triangulation per coarse face):
//  1. each non-site point p of cell s is assigned to the coarse triangle
//     incident to s's vertex that is nearest to p (exact point-triangle
//     distance), at the barycentric coordinates of its closest point there;
//  2. a closest point on an edge of that triangle (p projects outside it)
//     makes p an *edge point* of that edge, at its parameter t along the edge
//     (quantised to k / 2^20, so every face sharing the edge sees the same
//     points in the same order); otherwise p is an *interior point*
//     (barycentrics clamped to >= interior_margin, so it lies strictly inside);
//  3. each coarse triangle is laid out in its own plane (its true shape,
//     corner coordinates rounded to 2^-10 of its first edge so that edge
//     points are exactly collinear) and its corners, the edge points of its
//     three edges and its interior points are triangulated by a 2D Delaunay
//     triangulation (exact predicates): the convex hull is the triangle, so
//     the result subdivides it, and neighbouring faces split a shared edge at
//     the same points -> a closed coarse mesh stays closed, with the same
//     genus and components.
// Vertices sit at the input points themselves (the sites' included). Points
// at the same position (in 3D, or after clamping in a face's plane) become
// one vertex (counted). Points of a site in no face are dropped (counted).
//  4. (delaunay_flips) edges shared by two triangles are flipped while their
//     opposite angles sum to more than pi, unless the other diagonal already is
//     an edge or the new triangles would fold: the slivers along the coarse
//     edges go, vertices, face count and topology stay.
// The connectivity comes from the projection onto the coarse face, so where
// the surface bends strongly inside one coarse face some triangles fold over
// (counted in `folded_triangles`: normal opposite to the coarse face's).
#pragma once

#include "framework/points/graph_voronoi.h"
#include "framework/types.h"

#include <cstdint>

namespace arcs {

struct FullResolutionOptions {
  double interior_margin = 1e-4;  // smallest barycentric coordinate of an interior point
  double corner_margin = 1e-3;    // edge points closer than this (in t) to a corner become interior
  bool delaunay_flips = true;     // then flip edges to the surface Delaunay condition (see below)
  void Check() const;             // throws OptionError
};

struct FullResolutionStats {
  std::int64_t input_points = 0;
  std::int64_t vertices = 0;          // vertices of the refined mesh
  std::int64_t interior_points = 0;   // non-site points inserted inside a face
  std::int64_t edge_points = 0;       // non-site points inserted on an edge
  std::int64_t merged_points = 0;     // rows at a position some other vertex already has
  std::int64_t dropped_points = 0;    // rows whose site is in no face (or removed outliers)
  std::int64_t folded_triangles = 0;  // triangles whose normal opposes their coarse face's
  std::int64_t flips = 0;             // Delaunay edge flips made
  double pct_points = 0;              // 100 * vertices / input_points
  double seconds = 0;                 // wall time of the refinement
};

// Refines `coarse` (the result of ReconstructGraphVoronoi on the same P, with
// triangulate = true) to full resolution. Throws Error when built without
// CGAL, InputError when `coarse` does not belong to P.
Mesh RefineGraphVoronoi(const MatrixX3d& P, const GraphVoronoiResult& coarse,
                        const FullResolutionOptions& opt = {}, FullResolutionStats* stats = nullptr);

}  // namespace arcs
