// Winding-number voxelization (Luo et al., "Differentiable Voxelization and
// Mesh Morphing", Alg. 1 and 2) on regular grids, with the decisions of
// docs/voxelization.md:
//
//  * Occupancy of node q is w(q) > 1/2 for the generalized winding number w
//    (per-triangle solid angles with atan2, paper eq. 7/8, in double). With
//    orientation "abs" (default) the test is |w| > 1/2, so inward-oriented
//    meshes (w = -1 inside) voxelize like outward ones.
//  * method "exact": the O(#F) sum at every node (Alg. 1, parallel over nodes).
//    method "naive": the paper's eq. 4 (centroid/normal discretisation), values
//    only. method "ray_parity": crossings of +z rays per grid column (Embree;
//    the trimesh "contains" baseline), see ray_parity.h.
//    method "fast": for a mesh whose every edge is balanced (as many a->b as
//    b->a half-edges: closed in the chain sense, orientation-free) w is
//    constant off the surface, so the grid is split into the connected
//    components of nodes joined by grid edges that no triangle crosses
//    (crossings found conservatively), and w is the exact sum at one node per
//    component: the sign equals the exact sum's at every node by
//    construction. For a mesh with boundary, the hierarchical winding number
//    (FastWindingNumber, beta) is evaluated everywhere and nodes with
//    ||w| - 1/2| < exact_band are re-evaluated with the exact sum.
//  * Open meshes (open_mesh): "none" = plain threshold; "flip_dup" = the
//    paper's Alg. 2 (copy offset by -epsilon along vertex normals, faces
//    flipped) then the threshold; "auto" (default) = threshold, plus a thin
//    shell (nodes within max(epsilon/2, 0.87 h) of a "sheet" face) where a face
//    does not separate occupied from empty space (both sides of the face, at
//    +-h/2 along its normal, get the same threshold answer). A leaky solid
//    stays a solid; an open sheet becomes a shell about two voxels thick.
//    Meshes without boundary are never changed by "auto".
//  * Degenerate input: faces with repeated indices or an exactly zero cross
//    product are dropped (their solid angle is 0); non-finite coordinates or
//    bad indices are an InputError; an empty mesh gives an empty (all-0) grid.
//    No NaN is ever produced.
#pragma once

#include "framework/types.h"

#include <cstdint>
#include <string>
#include <vector>

namespace arcs {

// (r, r, r) nodes of linspace(lo[a], hi[a], r) per axis.
GridInfo CubeGrid(int resolution, const Vec3& lo, const Vec3& hi);
// Coordinate of node `i` on axis `a`: min + i * (max - min) / (n - 1) (the
// one formula used everywhere in this module).
double GridCoord(const GridInfo& g, int axis, int i);
// Every node as a row, in GridInfo order (x fastest).
MatrixX3d GridNodes(const GridInfo& g);

struct VoxelizeOptions {
  std::string method = "fast";       // exact | fast | naive | ray_parity
  std::string output = "occupancy";  // occupancy (0 / 1) | winding (w, after `orientation`)
  std::string open_mesh = "auto";    // auto | none | flip_dup
  std::string orientation = "abs";   // abs: occupancy |w| > 1/2 | as_is: w > 1/2
  double epsilon = 0.01;    // Alg. 2 offset (paper: 0.01); auto: minimum shell thickness
  double beta = 2.0;        // FastWindingNumber far-field acceptance (distance / radius)
  double exact_band = 0.1;  // fast with boundary: exact sum where ||w| - 1/2| < band
  void Check() const;
};

struct VoxelizeReport {
  std::string path;                 // exact | flood_fill | hierarchy | naive | ray_parity
  bool balanced = false;            // every edge balanced (no boundary in the chain sense)
  std::int64_t unbalanced_edges = 0;
  std::int64_t dropped_faces = 0;   // degenerate faces removed
  std::int64_t components = 0;      // flood_fill: grid components
  std::int64_t exact_evaluations = 0;
  std::int64_t sheet_faces = 0;     // auto rule
  std::int64_t shell_nodes = 0;     // auto rule: nodes set by the shell only
  std::int64_t occupied = 0;
};

VolumeGrid Voxelize(const Mesh& mesh, const GridInfo& grid, const VoxelizeOptions& options,
                    VoxelizeReport* report = nullptr);

// The same inside rule at arbitrary points Q (SDF signs of scattered
// samples): the threshold of `orientation` on the hierarchical winding number
// with the exact band (method fast; a balanced mesh gets no flood fill here,
// it needs grid edges), the exact or the naive sum; then, for a mesh with
// unbalanced edges under open_mesh "auto", the thin shell of the sheet faces
// with the node spacing `h` a grid would have. 1 = inside. The report's
// shell_nodes counts points made inside by the shell only.
std::vector<std::uint8_t> OccupancyAtPoints(const Mesh& mesh, const MatrixX3d& Q, double h,
                                            const VoxelizeOptions& options, VoxelizeReport* report = nullptr);

// Paper Alg. 2: V' = V - epsilon * N (area-weighted vertex normals; zero
// normals give no offset), F' = F flipped, returns (V u V', F u F').
Mesh FlipDuplicate(const Mesh& mesh, double epsilon);

// Paper eq. 4: w(q) = 1/(4 pi) sum_i <n_i, c_i - q> / |c_i - q|^3 * A_i; a
// face whose centroid coincides with q contributes 0.
VectorXd WindingNumbersNaive(const Mesh& mesh, const MatrixX3d& Q);

// Faces with repeated indices or an exactly zero cross product removed.
Mesh DropDegenerateFaces(const Mesh& mesh, std::int64_t* dropped = nullptr);
// Number of undirected edges whose half-edge counts a->b and b->a differ.
std::int64_t CountUnbalancedEdges(const Mesh& mesh);

// Removes every face with a vertex within `radius` of one of `centres`.
Mesh PunchHoles(const Mesh& mesh, const std::vector<Vec3>& centres, double radius);
// `count` well-spread mesh vertices (farthest-point order from vertex 0).
std::vector<Vec3> SpreadVertices(const Mesh& mesh, int count);

// Independent check of an occupancy grid against the exact sum (plain
// threshold with `orientation`): the hierarchical winding number at every
// node; the exact sum wherever the two disagree, wherever ||w_fast| - 1/2| <
// margin, and at `random_nodes` random nodes (seeded).
struct SignCheck {
  std::int64_t nodes = 0;
  std::int64_t fast_disagreements = 0;  // occupancy vs the hierarchy's sign
  std::int64_t exact_checked = 0;
  std::int64_t differences = 0;         // occupancy vs the exact sum's sign
};
SignCheck VerifyOccupancy(const Mesh& mesh, const VolumeGrid& occupancy, const std::string& orientation,
                          double margin = 0.1, std::int64_t random_nodes = 10000, std::uint64_t seed = 1);

}  // namespace arcs
