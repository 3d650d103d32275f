// Normal estimation and consistent orientation for point clouds without
// normals (scans), the input of reconstructors that need oriented points
// (ball pivoting, screened Poisson).
//
// Estimation: CGAL jet_estimate_normals (a quadric jet fitted to the k
// nearest neighbours; Cazals & Pouget) or pca_estimate_normals (the smallest
// principal axis of the k neighbours). Orientation ("mst"): CGAL
// mst_orient_normals (Hoppe et al. 1992): a Riemannian graph of the k
// nearest neighbours weighted by 1 - |n_i . n_j|, its minimum spanning tree
// grown from the point of largest z, whose normal is set to point to +z; for
// a closed surface that point's outward normal is +z, so the whole component
// ends up outward. Points the graph does not reach (other components) are
// oriented away from the centroid and counted. "centroid" orients every
// normal away from the centroid (right for star-shaped, convex-ish shapes),
// "none" leaves the signs of the fit (arbitrary).
#pragma once

#include "framework/types.h"

#include <string>

namespace arcs {

struct NormalOptions {
  // Neighbours of the fit, and of the orientation graph (CGAL's examples:
  // 18 for jet fitting). Range 3..1000 (clamped to #points - 1).
  int k = 18;
  // "jet" (quadric fit, robust on curved surfaces) or "pca" (plane fit).
  std::string method = "jet";
  // "mst", "centroid" or "none" (see above).
  std::string orientation = "mst";
  void Check() const;  // OptionError naming the field
};

struct NormalReport {
  int unoriented = 0;  // mst: points outside the MST's component (oriented by the centroid rule)
};

// Unit normals for the rows of P. Throws Error on fewer than 3 points or a
// non-finite coordinate (naming the row), and when arcs was built without
// CGAL. Deterministic (sequential CGAL).
MatrixX3d EstimateNormals(const MatrixX3d& P, const NormalOptions& options, NormalReport* report = nullptr);

}  // namespace arcs
