// Reach for the Spheres (Sellán, Batty, Stein, SIGGRAPH Asia 2023): the RFTA
// paper's third column. A triangle mesh starts as a sphere around the shape
// and flows toward the tangency points of the SDF spheres (every sample
// (p_i, s_i) is a sphere of centre p_i and radius |s_i| that a feasible
// surface touches without entering), remeshing the region that is not yet
// tangent. It never changes topology: the output has the genus of the start
// (0). Described in ../shared/notes/baselines.md (RFTS section); the defaults
// are those of the public implementation (gpytoolbox reach_for_the_spheres,
// 3D).
//
// One iteration (numbers as in the notes):
//  (1) batch: `batch_size` samples drawn without replacement, plus every
//      sample with s <= 0;
//  (2) closest point on the current mesh for each (distance d, face,
//      barycentrics), gap g = |s| - d, w = closest - sample;
//  (3) side σ = -sign(w · face normal), or sign(s) where a barycentric
//      weight is below `barycentric_threshold` (closest point on an edge or
//      a vertex, where the face normal is not the surface's);
//  (4) target on the sphere c = u + w σ s / max(tol/2, d);
//  (5) a sample is valid iff |g| < tol; the faces of invalid samples are the
//      active region (remeshed, see (11));
//  (6) least squares: A = barycentric weights (a zero row for a clamped
//      sample, |s| >= clamp, that the mesh does not enter: g < 0), c the
//      targets, M the Voronoi mass matrix, R = I / |batch|;
//  (7) step t from the line-search formula n_p = -AᵀR(AV - c),
//      t = -(<AV - c, R A n_p> + 0.01 |n_p|²) / <A n_p, R A n_p>, NaN -> 0,
//      clamped to [min_step, max_step];
//  (8) implicit step (M + t AᵀRA) V' = M V + t AᵀR c (sparse Cholesky);
//  (9) singularity guard: a non-finite vertex, a failed factorisation, a
//      zero-area face or a non-manifold edge restores the last converged
//      mesh and stops (never a crash); so does a diverging flow (ours: a
//      vertex beyond twice the start sphere's radius or the box, or a mesh
//      with more than max_area_ratio times the sample box's surface area);
// (10) convergence: err = |AV' - c| / |batch| after the step; after
//      `patience` iterations without an improvement of 1e-3 tol a mesh still
//      coarser than min_h is saved as "last converged", h is halved (not
//      below min_h) and the count and best error start afresh; at min_h
//      nothing is saved; the flow stops after the step when no sample was
//      invalid, or after `max_stall` iterations without improvement;
// (11) remeshing (framework/rfts/remesh.h, Botsch–Kobbelt) of the active
//      faces grown twice by one-rings, the patch boundary fixed.
//
// Frame. The samples are mapped by x_w = (x - centre) / scale, with centre
// the middle of their bounding box and scale half its largest extent, so
// the paper's protocol (samples on [-1, 1]³, shape in [-0.5, 0.5]³) is the
// identity; tol, the edge lengths and the initial sphere are in that frame,
// the output is mapped back.
//
// Deterministic: the batches come from ctx.MakeRng("rfts") (the official
// code seeds its own generator with 68); the closest-point queries run in
// parallel with per-index outputs; the solve and the remesher are serial. Same
// seed -> same mesh at any thread count.
#pragma once

#include "framework/context.h"
#include "framework/types.h"

#include <cstdint>
#include <string>

namespace arcs {

struct RftsOptions {
  int max_iterations = 20000;        // official 3D default
  double tol = 1e-2;                 // absolute tangency tolerance, working frame (official)
  double initial_edge_length = 0.2;  // h at the start (official)
  // Smallest h; 0 = the official heuristic clip(2 · mean nearest-neighbour
  // distance of the sample points, 0.001, 0.1) (working frame).
  double min_edge_length = 0.0;
  bool line_search = true;           // official: on
  double min_step = 1e-6;            // t clamp (official)
  double max_step = 50.0;            // t clamp (official)
  double fixed_step = 10.0;          // t when line_search is off (official dt)
  std::int64_t batch_size = 20000;   // random samples per iteration (official 3D); 0 = all
  int remesh_iterations = 1;         // Botsch–Kobbelt rounds per flow step (official)
  double split_ratio = 1.4;          // remesher: split > ratio·h
  double collapse_ratio = 0.7;       // remesher: collapse < ratio·h
  int patience = 10;                 // iterations without improvement before h is halved
  int max_stall = 100;               // iterations without improvement (at min_h) before stopping
  double barycentric_threshold = 1e-3;  // below: the side is taken from the sign of s
  int initial_subdivisions = 2;      // start: icosphere (official: 2 subdivisions, 162 vertices)
  double initial_radius = 1.0;       // of the start sphere, centred at the origin, working frame (official: 1)
  // Divergence guard (ours): more mesh area than this times the surface of
  // the samples' bounding box counts as a singularity (see (9)).
  double max_area_ratio = 4.0;
  void Check() const;
};

struct RftsResult {
  Mesh mesh;                   // input frame, outward faces, genus 0
  int iterations = 0;          // flow steps taken
  int halvings = 0;            // times h was halved
  double min_edge_length = 0;  // min_h used (working frame)
  double final_edge_length = 0;  // h at the end
  double final_error = 0;      // err of the last iteration
  std::int64_t final_invalid = 0;  // invalid samples of the last batch
  // "converged" (no invalid sample), "stalled" (max_stall at min_h),
  // "max_iterations", "singularity: WHAT" (the last converged mesh is
  // returned), or "cancelled" is thrown instead.
  std::string stop_reason;
  bool singular = false;
  double query_s = 0, solve_s = 0, remesh_s = 0;  // wall time of the parts
};

// Throws arcs::Error naming the problem (prefixed "rfts: ") unless the
// samples are 3D, as many points as values, at least 2, all finite, with both
// an inside (s < 0) and an outside (s > 0) sample; then runs the flow.
RftsResult ReachForTheSpheres(const SdfSamples& samples, const RftsOptions& options, const Context& ctx);

// The Voronoi mass matrix diagonal (Meyer et al. 2003: mixed areas, half /
// quarter the area at obtuse triangles), one entry per vertex.
VectorXd VoronoiMass(const Mesh& mesh);

}  // namespace arcs
