// The fine-tuner of Reach for the Arcs (paper §4.2, Supplemental Algorithm 3):
// a local–global iteration that reconstructs a surface from the current
// tangency points, moves every sphere's points along the sphere towards the
// projection of the surface's closest point (geodesic transport with step τ,
// halved until feasible), adds points to spheres the surface cuts into (up to
// n_max per sphere, one more per iteration when the cut is severe:
// |t_i| < 4/5 |s_i|), gives spheres without a point a "second chance", and
// makes every moved point feasible again against a batch of spheres of both
// signs (Algorithm 2).
//
// Units: the unit frame of sphere_set.h (τ and tol in [0,1]^d units).
//
// Dimensions. The reconstructed surface Ω^k is reached through TuningSurface
// (closest point + inside test): a triangle mesh in 3D
// (MakeMeshTuningSurface: the closest-point BVH and the fast winding number),
// a polyline in 2D (MakePolylineTuningSurface, FineTune2D). The 3D
// entry point with a PointsToMesh reconstructor is unchanged and gives the
// same results as before the generalisation, bit for bit. In 2D (samples.dim
// = 2, all points with z = 0) geodesic transport rotates about the z axis.
#pragma once

#include "framework/context.h"
#include "framework/rfta/arc_projector.h"
#include "framework/rfta/sphere_set.h"
#include "framework/types.h"

#include <functional>
#include <memory>
#include <vector>

namespace arcs {

struct FineTuneOptions {
  int iterations = 10;              // k_max (paper Supplemental default 10; Table 1/2 runs: 20)
  int max_points_per_sphere = 3;    // n_max (paper default 3; Table 1/2 runs: 30)
  std::int64_t batch_size = 10000;  // b: constraint spheres per iteration, both signs, without replacement (paper §4.2)
  double tau = 1e-2;                // geodesic step towards the target, unit frame (paper §4.2: τ = 10^-2)
  int halvings = 20;                // τ halvings before giving up a move (official line_search_iters)
  double severe_ratio = 0.8;        // |t_i| < ratio |s_i|: severe intersection, the point count may grow (paper: 4/5)
  FeasibleSearchOptions search;     // Alg. 2 settings and tol (shared with ArcProjectorOptions)
  double zero_radius = 1e-12;       // |s|/scale <= this: no sphere
  // When no halving of the step gives a feasible point: true = jump to the
  // target and let Alg. 2 repair it (the official code); false = stay put
  // (the last feasible point, as the paper's text argues).
  bool jump_when_blocked = true;
  // Spheres the surface misses keep only their moved closest point (paper
  // Alg. 3 line 11) when false; keep all their points, the closest moved,
  // when true.
  bool keep_points_when_missed = false;
  // After the last iteration, every point is checked against all spheres, not
  // only a batch (the batches of §4.2 leave points that some other sphere
  // contains, i.e. points the SDF data rules out as surface points; issue 10,
  // criterion 4). kRepair (the default): Alg. 2 against all spheres, dropping
  // the points it cannot fix; kDrop: drop them all; kOff: keep them (the paper's
  // algorithm as written). The check's counts are measured in every mode
  // (FineTuneResult::final_*), kOff included. repair against drop, measured
  // on the paper preset (docs/decisions.md, "Final check"): lower mean
  // Chamfer, E_SDF and Hausdorff over the bench set at n = 30, 40 and 50;
  // Fig. 9's fertility in one component at 3 of 8 seeds against drop's 4
  // (paired), so no topology gain; at n <= 20 (N <= b) the two agree bit for bit.
  enum class FinalCheck { kOff, kDrop, kRepair };
  static constexpr EnumName<FinalCheck> kFinalCheckNames[] = {
      {FinalCheck::kOff, "off"}, {FinalCheck::kDrop, "drop"}, {FinalCheck::kRepair, "repair"}};
  // The one default of the fine_tune and rfta stages (both read it from here).
  static constexpr FinalCheck kDefaultFinalCheck = FinalCheck::kRepair;
  FinalCheck final_check = kDefaultFinalCheck;
  void Check() const;
};

// Reconstructs a mesh (input frame) from oriented points (input frame).
using PointsToMesh = std::function<Mesh(const PointCloud&)>;

// What fine-tuning asks of a reconstructed surface Ω^k (paper §4.2), in the
// unit frame: closest points and the inside test (winding number > 1/2).
// Queries are const and may run in parallel; answers must not depend on the
// thread count.
class TuningSurface {
 public:
  virtual ~TuningSurface() = default;
  // Builds the query structures; called once, before any query.
  virtual void Prepare() = 0;
  // Squared distances and closest points of every row of Q (outputs resized).
  virtual void ClosestPoints(const MatrixX3d& Q, VectorXd* sq_dist, MatrixX3d* points) const = 0;
  // Squared distance to the closest point of one query, and that point.
  // `bound`: a squared distance the answer is known not to exceed (a search
  // radius; the answer is the same); infinity when unknown.
  virtual double Closest(const Vec3& q, Vec3* point, double bound) const = 0;
  // Generalised winding numbers of the rows of Q (> 0.5 = inside).
  virtual VectorXd WindingNumbers(const MatrixX3d& Q) const = 0;
  // ClosestPoints and WindingNumbers of the same rows; a surface that can
  // answer both from one search does (the mesh: the inside test from the
  // closest point's pseudonormal).
  virtual void ClosestPointsAndWindingNumbers(const MatrixX3d& Q, VectorXd* sq_dist, MatrixX3d* points,
                                              VectorXd* winding) const {
    ClosestPoints(Q, sq_dist, points);
    *winding = WindingNumbers(Q);
  }
};

// A triangle mesh already in the unit frame as a TuningSurface (the 3D path).
std::unique_ptr<TuningSurface> MakeMeshTuningSurface(Mesh unit_frame_mesh);

// A polyline already in the unit frame as a TuningSurface (the 2D path):
// closest points by SegmentBvh, inside by the 2D winding number.
std::unique_ptr<TuningSurface> MakePolylineTuningSurface(Polyline unit_frame_curve);

// Reconstructs a surface from oriented points (input frame) and returns it
// mapped into `frame`'s unit frame; nullptr = an empty reconstruction.
using PointsToSurface = std::function<std::unique_ptr<TuningSurface>(const PointCloud&, const UnitFrame& frame)>;

struct FineTuneIteration {
  std::int64_t points = 0;       // points after the iteration
  std::int64_t intersected = 0;  // spheres the surface cut into
  std::int64_t too_far = 0;      // spheres the surface missed
  std::int64_t tangent = 0;      // spheres within tol of the surface
  std::int64_t second_chance = 0;  // spheres that got their first point here
  std::int64_t dropped = 0;      // candidates still infeasible after Alg. 2
  double reconstruct_s = 0, query_s = 0, update_s = 0;  // wall time of the parts
};

struct FineTuneResult {
  PointCloud points;        // input frame, unit outward normals (eq. 2)
  std::vector<int> sample;  // sphere (SDF sample) of each point
  std::vector<FineTuneIteration> iterations;
  bool stopped_early = false;  // the reconstructor failed or gave an empty mesh: the last good points are kept
  std::string stop_reason;
  // The final check against all spheres (FineTuneOptions::final_check),
  // measured in every mode: points inside some sphere other than their own by
  // more than tol before the check (final_infeasible_before); of those, the
  // ones Alg. 2 moved back onto a feasible arc (kRepair) and the ones removed
  // (kDrop, and kRepair's failures); and the points of the result that still
  // violate a sphere, counted again after the check (final_infeasible: 0 with
  // kDrop / kRepair, final_infeasible_before with kOff).
  std::int64_t final_infeasible_before = 0;
  std::int64_t final_repaired = 0;
  std::int64_t final_dropped = 0;
  std::int64_t final_infeasible = 0;
  double final_check_s = 0;  // wall time of the check and the recount
};

// Runs k_max fine-tuning iterations from the tangency points `initial`
// (`initial_sample[j]` = the SDF sample of point j). `reconstruct` is the
// configured surface reconstructor (screened Poisson by default); its meshes
// are queried through MakeMeshTuningSurface (3D).
FineTuneResult FineTune(const SdfSamples& samples, const PointCloud& initial, const std::vector<int>& initial_sample,
                        const PointsToMesh& reconstruct, const FineTuneOptions& options, const Context& ctx);

// The same with any surface type (2D polylines, or other 3D surfaces).
FineTuneResult FineTune(const SdfSamples& samples, const PointCloud& initial, const std::vector<int>& initial_sample,
                        const PointsToSurface& reconstruct, const FineTuneOptions& options, const Context& ctx);

// Reconstructs closed polylines (input frame, z = 0) from oriented 2D points.
using PointsToCurve = std::function<Polyline(const PointCloud&)>;

// The 2D twin of the PointsToMesh entry point (samples.dim must be 2): its
// curves are queried through MakePolylineTuningSurface. An empty curve stops
// the iterations early, as an empty mesh does in 3D.
FineTuneResult FineTune2D(const SdfSamples& samples, const PointCloud& initial, const std::vector<int>& initial_sample,
                          const PointsToCurve& reconstruct, const FineTuneOptions& options, const Context& ctx);

}  // namespace arcs
