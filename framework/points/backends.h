// The third-party back-ends of the point-cloud reconstructors and of normal
// estimation, behind plain types (no CGAL / Open3D type in this header).
//
// Each function lives in its own translation unit (points/cgal/*.cpp,
// points/open3d/*.cpp), compiled into its own small static library so the
// library's headers and flags (CGAL's -frounding-math) stay there. Built
// without the package, a function throws Error("... built without X: install
// libX-dev"). Callers (point_reconstructors.cpp, normals.cpp) validate and
// clean the input first: finite coordinates, no duplicate positions, enough
// points, unit normals where required.
#pragma once

#include "framework/types.h"

#include <cstdint>
#include <vector>

namespace arcs::points_detail {

bool CgalAvailable();
bool Open3dAvailable();

// CGAL Alpha_shape_3 in REGULARIZED mode at squared radius `alpha_sq`: the
// boundary facets of the solid (REGULAR facets: one interior and one exterior
// cell), each wound outward from its interior cell. Vertices are the rows of
// P (unused ones included). alpha_sq <= 0 uses CGAL's find_optimal_alpha(1)
// (the smallest alpha whose solid is one component with every point on its
// boundary or inside) times optimal_scale^2 (radius times optimal_scale). `used_alpha_sq` receives the value used. Throws Error
// when the points span no volume (coplanar / collinear).
Mesh CgalAlphaShape(const MatrixX3d& P, double alpha_sq, double* used_alpha_sq = nullptr,
                    double optimal_scale = 1.0);

// CGAL advancing_front_surface_reconstruction (Cohen-Steiner & Da): faces
// index the rows of P, oriented consistently per component (orientation
// itself arbitrary). radius_ratio_bound and beta are CGAL's parameters.
Mesh CgalAdvancingFront(const MatrixX3d& P, double radius_ratio_bound, double beta);

// Unoriented normals: CGAL jet_estimate_normals (jet = true, quadric fit
// of order 2) or pca_estimate_normals, k neighbours.
MatrixX3d CgalEstimateNormals(const MatrixX3d& P, int k, bool jet);

// CGAL mst_orient_normals (Hoppe et al. 1992: Riemannian graph of k
// neighbours, MST from the point of largest z, whose normal is set to +z).
// Flips rows of N in place; returns per point whether it was oriented
// (points in other connected components of the k-graph are not).
std::vector<char> CgalMstOrientNormals(const MatrixX3d& P, MatrixX3d* N, int k);

// Open3D TriangleMesh::CreateFromPointCloudBallPivoting (Bernardini et al.
// 1999) with the given radii (ascending); normals required (unit). Faces
// index the rows of P; Open3D orients each face by the normals.
Mesh Open3dBallPivoting(const MatrixX3d& P, const MatrixX3d& N, const std::vector<double>& radii);

}  // namespace arcs::points_detail
