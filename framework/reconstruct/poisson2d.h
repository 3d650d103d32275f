// Screened Poisson reconstruction in the plane (after Kazhdan & Hoppe 2013,
// our own discretisation; no library does 2D): oriented 2D points -> closed
// polylines, the reconstructor of 2D Reach for the Arcs.
//
// Discretisation. A square grid of res x res cells covers the points'
// bounding box enlarged `scale` times (cell size h); the indicator χ lives on
// the (res+1)^2 nodes, bilinear in between. Each point p carries a length a_p
// (its share of the curve, from the distance to its k-th nearest neighbour:
// a_p = 2 r_k / k, clamped to [0.1, 10] x the median, so clustered points
// count once, as sPSR's density weights do). Its inward normal -n_p a_p is
// spread over the x- and y-edges of the grid within R_p = max(1, smoothing *
// a_p / h) cells by the separable biweight (1 - t^2)^2 (normalised): the
// gradient field V. Sparse (e.g. stray) points thus spread thin, as they fall
// into coarse octree nodes in PoissonRecon, instead of making small islands.
// χ minimises
//   Σ_edges (Dχ - h V)^2  +  Σ_p β χ(p)^2,    β = α ā / h,
// (D: node differences along an edge; Neumann boundary: no extra terms;
// ā = mean a_p, the same screening weight for every point), i.e.
// (L + β Σ_p b_p b_p^T) χ = D^T (h V), with L the 5-point graph Laplacian
// and b_p the bilinear weights of p. The jump of χ across the curve is 1
// (inside higher) and screening pulls χ to 0 at the points.
// Screening weight α: per unit curve length *in cells*, so its balance with
// the gradient term does not change with the resolution (PoissonRecon scales
// its weight with the depth for the same reason). α = 10 is the paper's value
// in this scaling (docs/planar.md has the measurements).
// The linear system is SPD (the screening fixes the constant) and solved by a
// sparse Cholesky (Eigen SimplicialLDLT): deterministic, single-threaded.
// The iso-value is the mean of χ at the points; the contour is extracted by
// marching squares (framework/geometry) with the inside (χ above the
// iso-value) on the left of every edge: outer curves counter-clockwise,
// holes clockwise. The output is in the points' frame (z = 0).
#pragma once

#include "framework/context.h"
#include "framework/types.h"

namespace arcs {

struct Poisson2DOptions {
  int resolution = 0;        // grid cells per side; 0 = automatic: 4 sqrt(N) rounded up to a power of two, in [64, 1024]
  int resolution_shift = 0;  // added to the automatic resolution's power of two (-1 = half as fine)
  double screening = 10.0;   // α (paper: 10), per unit curve length in cells; 0 = unscreened Poisson
  double scale = 1.25;       // grid side / largest bounding-box extent of the points (> 1)
  int neighbours = 8;        // k of the density estimate (a_p = 2 r_k / k)
  double smoothing = 3.0;    // splatting radius of a point's normal: max(1 cell, smoothing * a_p)
  void Check() const;
};

// The resolution the options give for N points.
int Poisson2DResolution(const Poisson2DOptions& options, int num_points);

struct Poisson2DInfo {
  int resolution = 0;      // cells per side used
  double iso_value = 0.0;  // the extracted level of χ
};

// Oriented points (P: N x 3 with z = 0, or N x 2 in the first two columns;
// N: unit normals pointing out) -> closed polylines (inside on the left).
// Throws Error on fewer than 3 points, missing normals, non-finite input,
// z != 0, or points that span no area (all on one point). May return an
// empty polyline (no contour found), which callers treat as a failure.
Polyline ReconstructPoisson2D(const PointCloud& points, const Poisson2DOptions& options, const Context& ctx,
                              Poisson2DInfo* info = nullptr);

}  // namespace arcs
