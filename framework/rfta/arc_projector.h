// The arc projector of Reach for the Arcs (paper §4.1, Supplemental
// Algorithms 1 and 2): for every sphere, the closest free-space sample is
// projected onto the sphere and then made feasible — moved along the sphere
// until no other sphere (of the same sign, from the constraint batch)
// contains it by more than tol. The result is the initial tangency point
// cloud a^0 with the normals of eq. (2).
//
// Units: everything here works in the unit frame of sphere_set.h (tol is in
// [0,1]^d units, as in the official code); ProjectToArcs maps its output back.
#pragma once

#include "framework/util/enum_names.h"

#include "framework/context.h"
#include "framework/rfta/sphere_set.h"
#include "framework/rfta/sphere_tree.h"
#include "framework/types.h"

#include <cstdint>
#include <vector>

namespace arcs {

// Which candidate Algorithm 2 takes when a point is inside >= 2 spheres.
// Default kClosest: with kFirst the point can cycle between pairs without
// converging; on the exact SDF of a ball (20^3 grid) kFirst drops 110 of 9261
// spheres after 20 steps, kClosest none, in fewer steps.
enum class PairChoice {
  kFirst,    // the official code: pairs in order of radius, first pair with an admissible candidate
  kClosest,  // the paper's Alg. 2 line 13: the admissible candidate closest to x over all pairs
};
inline constexpr EnumName<PairChoice> kPairChoiceNames[] = {{PairChoice::kClosest, "closest"},
                                                            {PairChoice::kFirst, "first"}};

// The settings of Algorithm 2 (make feasible) that the arc projector and the
// fine-tuner share, declared once (one option group, registry/bind.h).
struct FeasibleSearchOptions {
  int local_search_iters = 20;  // make-feasible steps per point (paper Alg. 2: 20)
  int local_searches = 0;       // k_search: containing spheres gathered per step; 0 = ceil(2 N^(1/d)) (paper §4.1)
  double tol = 1e-4;            // containment / tangency tolerance in [0,1]^d units (official tol)
  PairChoice pair_choice = PairChoice::kClosest;  // candidate rule for >= 2 containing spheres (paper Alg. 2; official: kFirst)
  void Check() const;
};

// Options of one make-feasible run (Algorithm 2).
struct MakeFeasibleOptions {
  int dim = 3;                 // 2: circle-circle intersections; 3: circles and trilateration (Fang 1986)
  int iterations = 20;         // local search steps (paper Alg. 2: 20; official local_search_iters)
  int k_search = 42;           // containing spheres gathered per step (official ceil(2 N^(1/d)); 42 at a 20^3 grid)
  double tol = 1e-4;           // containment / tangency tolerance, unit frame (official tol)
  PairChoice pair_choice = PairChoice::kClosest;  // see PairChoice (official: kFirst)
  void Check() const;
};

// Algorithm 2 for the point *x on sphere (center, radius) whose id in
// `constraints` is self_id (skipped there). Feasible = no other ball contains
// x by more than tol (|x - c| < r - tol). Each step gathers up to k_search
// balls with |x - c| - r < tol (deepest first), sorts them by radius, and
// moves x to the closest admissible point of the sphere's intersection with
// one of them (one ball) or with two of them (three-sphere trilateration);
// admissible = in the unit box (+- tol) and not inside the other gathered
// balls by more than tol. Stops early when a step cannot move x. Returns
// whether *x ends feasible; *x always stays on the sphere. `steps` (optional)
// receives the number of steps taken. `local` (optional): a list of the
// constraint balls near *x (SphereTree::CollectLocal with offset >= tol),
// used while x stays in its box; the result is the same without it.
// `known` (optional): what the caller already knows of the first test, at
// the point *x becomes on the sphere (OntoSphere): whether a ball of
// `constraints` other than self_id contains it by more than tol
// (SphereTree::AnyContains with offset -tol). Used only when that point is
// known.at to the bit; the answer is then the same without the query.
// `free_at_end` (optional) receives whether AnyContains(*x, -tol, self_id,
// local) is known to be false at the returned *x (the last test made was
// that query, or `known` said so): a caller that would ask it again may
// skip it. False does not mean contained (gather() may have decided).
struct KnownContainment {
  Vec3 at = Vec3::Zero();
  bool contained = false;
};
bool MakeFeasible(const SphereTree& constraints, const Vec3& center, double radius, int self_id,
                  const MakeFeasibleOptions& options, Vec3* x, int* steps = nullptr,
                  const SphereTree::LocalSet* local = nullptr, const KnownContainment* known = nullptr,
                  bool* free_at_end = nullptr);

// v moved radially onto the sphere (center, radius); the centre itself goes
// to center + radius e_x. MakeFeasible's projection (callers that predict its
// first point use this).
inline Vec3 OntoSphere(const Vec3& center, double radius, const Vec3& v) {
  const Vec3 d = v - center;
  const double n = d.norm();
  return n > 0.0 ? Vec3(center + (radius / n) * d) : Vec3(center + radius * Vec3::UnitX());
}

// b distinct indices of [0, n) drawn uniformly without replacement, sorted
// (n <= b or b == 0: all of [0, n)). The official code draws with
// replacement (rng.choice), which repeats spheres and so loses some.
std::vector<int> DrawBatch(std::int64_t n, std::int64_t b, Rng& rng);

struct ArcProjectorOptions {
  FeasibleSearchOptions search;     // Alg. 2 settings (shared with FineTuneOptions)
  std::int64_t batch_size = 10000;  // b: constraint spheres per sign, drawn without replacement when there are more (paper §4.2; 0 = all)
  double zero_radius = 1e-12;     // |s| / scale <= this: no sphere, no point (see SignSplitOptions)
  void Check() const;
};

struct ArcProjectorStats {
  std::int64_t spheres = 0;       // spheres that want a point (both signs)
  std::int64_t zero = 0;          // samples skipped as |s| ~ 0
  std::int64_t clamped = 0;       // spheres skipped as clamped (|s| >= clamp)
  std::int64_t feasible_at_projection = 0;  // feasible right after the projection
  std::int64_t made_feasible = 0;           // made feasible by Algorithm 2
  std::int64_t dropped = 0;                 // still infeasible: no point
  std::int64_t batch[2] = {0, 0};           // constraint spheres {positive, negative}
  int k_search = 0;                         // the k_search used
};

struct ArcProjection {
  PointCloud points;        // tangency points (input frame) with unit outward normals, eq. (2)
  std::vector<int> sample;  // the SDF sample (sphere) of each point, ascending
  ArcProjectorStats stats;
};

// The initial tangency set a^0 (Algorithm 1, lines 2–8): for each sign apart,
// each sphere's closest free point of that sign (kd-tree on the free points),
// projected onto the sphere, made feasible against a batch of spheres of the
// same sign; infeasible ones are dropped. Free points with an empty sign
// vector serve both signs. Normals n_i = sign(s_i) (p_i - a_i) / |p_i - a_i|
// point out of the shape. Throws arcs::Error for unusable samples, samples of
// one sign only, or no free points for a sign.
ArcProjection ProjectToArcs(const SdfSamples& samples, const FreeSpaceSamples& free,
                            const ArcProjectorOptions& options, const Context& ctx);

}  // namespace arcs
