// DCSDD: dual contouring of signed distance data (Carrera, Wang, Batty,
// Stein, Sellán 2026; gpytoolbox `dual_contouring_of_signed_distance_data`),
// implemented from the description in ../shared/notes/baselines.md.
//
// Classic dual contouring (framework/sdfmesh/dual_contouring.h, per-edge
// normals) gives the start; then an outer loop that uses what DC ignores:
// every SDF sample is a sphere that the surface must touch and not enter.
// Each outer iteration
//  1. triangulates the quads (shorter diagonal) with the current vertices;
//  2. takes the samples near the surface (|s| < `band` cell diagonals; a
//     random subset of them when there are more than `batch_size`) and tops
//     them up with randomly drawn other samples to `batch_size`;
//  3. finds each sample's closest point on the current mesh and assigns the
//     sample to the vertex of the grid cell that holds that point (when that
//     cell has no vertex: the closest triangle's vertex nearest to the point);
//     a sample whose distance minus radius exceeds `drop_distance` cell
//     diagonals is dropped;
//  4. re-solves every vertex x with its neighbours held, Gauss-Seidel over
//     eight colour classes of cells (parity of i, j, k; vertices of a class
//     share no face, so a class runs in parallel and the result does not
//     depend on the thread count; solving all at once overshoots, each vertex
//     correcting the same gap), up to `inner_iterations` Gauss-Newton steps of
//       sum_edges (dc_weight n_i.(x - p_i))^2
//     + sum_spheres (dist(c_j, fan(x)) - r_j)^2       (the fan: x's triangles)
//     + proximal_weight |x - x_prev|^2               (x_prev: the last step),
//     the sphere term linearised at the closest point q of the fan to c_j
//     (row beta_x u.dx = r_j - |q - c_j|, u = (q - c_j)/|q - c_j|, beta_x the
//     barycentric weight of x at q), each step by the truncated SVD
//     (`svd_threshold`), clamped to the cell;
//  5. moves each crossed edge's Hermite point and normal `blend` of the way
//     towards the plane fitted (least squares) to the vertices of the four
//     cells around the edge: the normal towards the plane's normal, the point
//     towards the plane's intersection with the edge.
// Random choices come from `seed` (the public implementation's shuffle is
// unseeded): the same seed gives the same mesh at any thread count.
#pragma once

#include "framework/context.h"
#include "framework/types.h"

#include <cstdint>

namespace arcs {

struct DcsddOptions {
  int iterations = 100;          // outer iterations (the source's default 100)
  std::int64_t batch_size = 200000;  // samples per outer iteration (the source: 200 000)
  double band = 3.0;             // near-surface band: |s| < band cell diagonals (the source: 3)
  double drop_distance = 1.0;    // drop a sample whose distance - radius exceeds this many cell diagonals (the source: 1)
  double dc_weight = 0.02;       // weight of the DC (Hermite plane) rows in the cell solve (the source: 0.02)
  double proximal_weight = 0.1;  // proximal term proximal_weight |x - x_prev|^2 (the source: sqrt(0.1) as row weight)
  double svd_threshold = 0.01;   // truncated SVD of the cell solve, relative to the largest singular value (the source: 0.01)
  int inner_iterations = 100;    // Gauss-Newton steps per cell and outer iteration, at most (the source: 100)
  double inner_tolerance = 1e-3; // a cell stops when its step is below this many cell diagonals (ours)
  double tolerance = 1e-4;       // stop the outer loop when no vertex moved more than this many cell diagonals (ours; 0 = never)
  double blend = 0.2;            // Hermite update towards the fitted planes (the source: 20 %)
  double dc_svd_threshold = 0.1; // the initial dual contouring's QEF threshold (DualContouringOptions' default)
  bool clamp_to_cell = true;     // keep every vertex in its cell (initial DC and every step)
  bool manifold = false;         // start from manifold DC (one vertex per MC sheet)
  std::uint64_t seed = 1;        // the random top-up of the batch
  void Check() const;
};

struct DcsddStats {
  int vertices = 0;
  int quads = 0;
  std::int64_t spheres_used = 0;     // samples assigned to a vertex in the last outer iteration
  int iterations = 0;                // outer iterations run
  double mean_inner_iterations = 0;  // per vertex, averaged over the outer iterations
  double mean_sphere_residual = 0;   // mean |dist(c, mesh) - r| over the last batch's assigned samples
  double initial_sphere_residual = 0;  // the same for the initial DC mesh (first batch)
};

// `samples`: SDF values on a regular 3D grid (samples.grid set), both signs
// present, finite (CheckSdfToMeshInput). The surface is the zero level set.
Mesh Dcsdd(const SdfSamples& samples, const DcsddOptions& options, const Context& ctx,
           DcsddStats* stats = nullptr);

}  // namespace arcs
