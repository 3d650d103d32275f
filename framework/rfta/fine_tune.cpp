#include "framework/rfta/fine_tune.h"

#include "framework/error.h"
#include "framework/rfta/sphere_set.h"
#include "framework/rfta/sphere_tree.h"
#include "framework/spatial/polyline_query.h"
#include "framework/spatial/pseudonormal_sign.h"
#include "framework/spatial/triangle_bvh.h"
#include "framework/spatial/winding_number.h"
#include "framework/util/parallel.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace arcs {

void FineTuneOptions::Check() const {
  ARCS_CHECK_OPTION(iterations >= 0 && iterations <= 10000, "iterations", iterations, "in [0, 10000]");
  ARCS_CHECK_OPTION(max_points_per_sphere >= 1 && max_points_per_sphere <= 1000, "max_points_per_sphere",
                    max_points_per_sphere, "in [1, 1000]");
  ARCS_CHECK_OPTION(batch_size >= 0 && batch_size <= 1000000000, "batch_size", batch_size,
                    "in [0, 1e9] (0 = all spheres)");
  ARCS_CHECK_OPTION(tau > 0 && tau < 1, "tau", tau, "in (0, 1)");
  ARCS_CHECK_OPTION(halvings >= 0 && halvings <= 60, "halvings", halvings, "in [0, 60]");
  ARCS_CHECK_OPTION(severe_ratio > 0 && severe_ratio <= 1, "severe_ratio", severe_ratio, "in (0, 1]");
  search.Check();
}

namespace {

using Clock = std::chrono::steady_clock;
double Since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// All spheres of both signs in one list (unit frame).
struct AllSpheres {
  MatrixX3d centers;
  VectorXd radii;
  std::vector<int> sample;     // SDF sample of each sphere
  std::vector<signed char> sign;
  std::vector<char> wants_point;
  int Size() const { return static_cast<int>(radii.size()); }
};

AllSpheres Combine(const SignedSpheres& s) {
  AllSpheres a;
  const int np = s.positive.Size(), nn = s.negative.Size();
  a.centers.resize(np + nn, 3);
  a.radii.resize(np + nn);
  for (int k = 0; k < 2; ++k) {
    const SphereSet& set = k == 0 ? s.positive : s.negative;
    const int off = k == 0 ? 0 : np;
    if (set.Size()) {
      a.centers.middleRows(off, set.Size()) = set.centers;
      a.radii.segment(off, set.Size()) = set.radii;
    }
    for (int i = 0; i < set.Size(); ++i) {
      a.sample.push_back(set.sample[i]);
      a.sign.push_back(k == 0 ? 1 : -1);
      a.wants_point.push_back(set.wants_point.empty() ? 1 : set.wants_point[i]);
    }
  }
  return a;
}

// Rotates p (on the sphere (c, r)) towards q along the great circle by at most
// `step` arc length, halving the step until the point is feasible (no batch
// sphere contains it by more than tol). Returns p itself when no step is
// feasible (p is the last known feasible point, paper §4.2), or q when
// `jump_when_blocked` (the official code; Alg. 2 then repairs q).
// *tested: whether the point returned was found feasible here.
// In 2D (dim 2) every point has z = 0 and the rotation axis is the z axis.
Vec3 Transport(const Vec3& p, const Vec3& q, const Vec3& c, double r, double step, int halvings,
               const SphereTree& tree, double tol, int self, bool jump_when_blocked,
               const SphereTree::LocalSet* local, int dim, bool* tested) {
  *tested = false;
  const Vec3 u = (p - c) / r, v = (q - c) / r;
  const double cosang = std::clamp(u.dot(v), -1.0, 1.0);
  const double full = std::acos(cosang);
  if (full < 1e-15) return q;
  Vec3 axis = u.cross(v);
  if (axis.norm() < 1e-14) {  // antipodal: any perpendicular axis (in 2D: the plane's normal)
    axis = dim == 2 ? Vec3(0, 0, 1) : Vec3(u.unitOrthogonal());
  }
  axis.normalize();
  double theta = std::min(step / r, full);
  // The balls that blocked earlier halvings are tested first: a ball that
  // contains one candidate usually contains the next, half-way back to p,
  // and then no tree query is needed (the same answers).
  int blockers[8];
  int nb = 0;
  for (int h = 0; h <= halvings; ++h) {
    const Vec3 x = c + r * Eigen::AngleAxisd(theta, axis).toRotationMatrix() * u;
    bool blocked = false;
    for (int b = 0; b < nb && !blocked; ++b) blocked = tree.Contains(blockers[b], x, -tol, self);
    if (!blocked) {
      const int k = tree.FindContaining(x, -tol, self, local);
      if (k < 0) {
        *tested = true;
        return x;
      }
      if (nb < 8) blockers[nb++] = k;
      else blockers[h % 8] = k;
    }
    theta *= 0.5;
  }
  return jump_when_blocked ? q : p;
}

// Spheres up to local_radius scan a short list of the constraint balls near
// them (identical answers, far fewer tree traversals); larger ones query the
// tree. Returns the list to pass to the queries, or nullptr.
const SphereTree::LocalSet* LocalFor(const SphereTree& tree, const Vec3& c, double r, double local_radius,
                                     double tol, SphereTree::LocalSet* set) {
  if (r > local_radius) return nullptr;
  const Vec3 margin = Vec3::Constant(r + 2 * tol);
  tree.CollectLocal(c - margin, c + margin, tol, set);
  return set;
}

// The 3D surface: closest points by the triangle BVH; inside by the closest
// point's pseudonormal when the mesh is closed (screened Poisson's always is
// unless it reaches its cube: exact, and free beside the closest point),
// else by the fast winding number.
class MeshTuningSurface final : public TuningSurface {
 public:
  explicit MeshTuningSurface(Mesh m) : mesh_(std::move(m)) {}
  void Prepare() override {
    // One query per sphere centre, most of them far from the surface: the
    // oriented boxes prune those (armadillo n = 40: 20 centre passes 5.7 ->
    // 1.9 s) for a dearer build (2.4 -> 3.8 s); the Morton split keeps the
    // build cheap (the SAH one took 11 s).
    // The two builds are independent and each has serial parts: side by side.
    ParallelInvoke([&] { bvh_ = std::make_unique<TriangleBvh>(mesh_, TriangleBvh::BuildKind::kMortonOriented); },
                   [&] { sign_ = std::make_unique<PseudonormalSign>(mesh_); });
    if (!sign_->closed()) fwn_ = std::make_unique<FastWindingNumber>(mesh_);
  }
  void ClosestPointsAndWindingNumbers(const MatrixX3d& Q, VectorXd* sq_dist, MatrixX3d* points,
                                      VectorXd* winding) const override {
    if (fwn_) {
      TuningSurface::ClosestPointsAndWindingNumbers(Q, sq_dist, points, winding);
      return;
    }
    Eigen::VectorXi faces;
    bvh_->ClosestPoints(Q, sq_dist, points, &faces);
    winding->resize(Q.rows());
    ParallelFor(Q.rows(), [&](std::int64_t b, std::int64_t e) {
      for (std::int64_t i = b; i < e; ++i) {
        const Vec3 q = Q.row(i).transpose();
        const int side = sign_->Side(q, points->row(i).transpose(), faces[i]);
        // Undecided (on the surface, a degenerate feature): the exact sum.
        (*winding)[i] = side > 0 ? 0.0 : side < 0 ? 1.0 : WindingNumberExact(mesh_, q);
      }
    }, 1024);
  }
  void ClosestPoints(const MatrixX3d& Q, VectorXd* sq_dist, MatrixX3d* points) const override {
    bvh_->ClosestPoints(Q, sq_dist, points);
  }
  double Closest(const Vec3& q, Vec3* point, double bound) const override {
    // The bound, widened against rounding, prunes the search; should it
    // still miss (it cannot by more than rounding), the unbounded query.
    TriangleBvh::Hit h = bvh_->Closest(q, bound * (1.0 + 1e-9) + 1e-300);
    if (h.face < 0) h = bvh_->Closest(q);
    *point = h.point;
    return h.sq_dist;
  }
  VectorXd WindingNumbers(const MatrixX3d& Q) const override {
    if (fwn_) return fwn_->Eval(Q);
    VectorXd sq, w;
    MatrixX3d p;
    ClosestPointsAndWindingNumbers(Q, &sq, &p, &w);
    return w;
  }

 private:
  Mesh mesh_;
  std::unique_ptr<TriangleBvh> bvh_;
  std::unique_ptr<PseudonormalSign> sign_;
  std::unique_ptr<FastWindingNumber> fwn_;  // only for a mesh that is not closed
};

// The 2D path: a polyline in the unit frame.
class PolylineTuningSurface final : public TuningSurface {
 public:
  explicit PolylineTuningSurface(Polyline c) : curve_(std::move(c)) {}
  void Prepare() override { bvh_ = std::make_unique<SegmentBvh>(curve_); }
  void ClosestPoints(const MatrixX3d& Q, VectorXd* sq_dist, MatrixX3d* points) const override {
    bvh_->ClosestPoints(Q, sq_dist, points);
  }
  double Closest(const Vec3& q, Vec3* point, double /*bound*/) const override {
    const SegmentBvh::Hit h = bvh_->Closest(q);
    *point = h.point;
    return h.sq_dist;
  }
  VectorXd WindingNumbers(const MatrixX3d& Q) const override { return WindingNumbers2D(curve_, Q); }

 private:
  Polyline curve_;
  std::unique_ptr<SegmentBvh> bvh_;
};

}  // namespace

std::unique_ptr<TuningSurface> MakeMeshTuningSurface(Mesh unit_frame_mesh) {
  return std::make_unique<MeshTuningSurface>(std::move(unit_frame_mesh));
}

FineTuneResult FineTune(const SdfSamples& samples, const PointCloud& initial, const std::vector<int>& initial_sample,
                        const PointsToMesh& reconstruct, const FineTuneOptions& options, const Context& ctx) {
  const PointsToSurface surface = [&](const PointCloud& pc, const UnitFrame& frame) -> std::unique_ptr<TuningSurface> {
    Mesh omega = reconstruct(pc);
    if (omega.Empty()) return nullptr;
    // Into the unit frame.
    for (int v = 0; v < omega.NumVertices(); ++v)
      omega.V.row(v) = frame.ToUnit(omega.V.row(v).transpose()).transpose();
    return MakeMeshTuningSurface(std::move(omega));
  };
  return FineTune(samples, initial, initial_sample, surface, options, ctx);
}

std::unique_ptr<TuningSurface> MakePolylineTuningSurface(Polyline unit_frame_curve) {
  return std::make_unique<PolylineTuningSurface>(std::move(unit_frame_curve));
}

FineTuneResult FineTune2D(const SdfSamples& samples, const PointCloud& initial, const std::vector<int>& initial_sample,
                          const PointsToCurve& reconstruct, const FineTuneOptions& options, const Context& ctx) {
  if (samples.dim != 2) throw Error("fine_tune (2D): the samples are " + std::to_string(samples.dim) + "D");
  const PointsToSurface surface = [&](const PointCloud& pc,
                                      const UnitFrame& frame) -> std::unique_ptr<TuningSurface> {
    Polyline c = reconstruct(pc);
    if (c.Empty()) return nullptr;
    for (int v = 0; v < c.NumVertices(); ++v) c.V.row(v) = frame.ToUnit(c.V.row(v).transpose()).transpose();
    c.V.col(2).setZero();  // exactly in the plane (ToUnit subtracts z = 0 translation)
    return MakePolylineTuningSurface(std::move(c));
  };
  return FineTune(samples, initial, initial_sample, surface, options, ctx);
}

FineTuneResult FineTune(const SdfSamples& samples, const PointCloud& initial, const std::vector<int>& initial_sample,
                        const PointsToSurface& reconstruct, const FineTuneOptions& options, const Context& ctx) {
  options.Check();
  CheckRftaSamples(samples, "fine_tune");
  if (static_cast<int>(initial_sample.size()) != initial.Size())
    throw Error("fine_tune: " + std::to_string(initial.Size()) + " points but " +
                std::to_string(initial_sample.size()) + " sample indices");
  SignSplitOptions so;
  so.zero_radius = options.zero_radius;
  const SignedSpheres split = SplitSpheresBySign(samples, so);
  RequireBothSigns(split, "fine_tune");
  const UnitFrame& frame = split.frame;
  const AllSpheres all = Combine(split);
  const int ns = all.Size();
  std::vector<int> sphere_of_sample(samples.Size(), -1);
  for (int g = 0; g < ns; ++g) sphere_of_sample[all.sample[g]] = g;

  MakeFeasibleOptions mf;
  mf.dim = samples.dim;
  mf.iterations = options.search.local_search_iters;
  mf.k_search = options.search.local_searches > 0 ? options.search.local_searches : LocalSearchHeuristic(split.num_samples, samples.dim);
  mf.tol = options.search.tol;
  mf.pair_choice = options.search.pair_choice;
  const double local_radius = 2.0 / SamplesPerAxis(split.num_samples, samples.dim);
  std::vector<int> ids(ns);  // sphere trees name the spheres by their index
  for (int g = 0; g < ns; ++g) ids[g] = g;

  // Current tangency points per sphere (unit frame).
  std::vector<std::vector<Vec3>> pts(ns);
  for (int j = 0; j < initial.Size(); ++j) {
    const int smp = initial_sample[j];
    if (smp < 0 || smp >= static_cast<int>(samples.Size()) || sphere_of_sample[smp] < 0)
      throw Error("fine_tune: point " + std::to_string(j) + " refers to sample " + std::to_string(smp) +
                  ", which has no sphere");
    pts[sphere_of_sample[smp]].push_back(frame.ToUnit(initial.P.row(j).transpose()));
  }

  auto to_cloud = [&](FineTuneResult* out) {
    std::int64_t n = 0;
    for (const auto& v : pts) n += static_cast<std::int64_t>(v.size());
    out->points.P.resize(n, 3);
    out->points.N.resize(n, 3);
    out->sample.resize(n);
    std::int64_t k = 0;
    for (int g = 0; g < ns; ++g) {
      const Vec3 c = all.centers.row(g).transpose();
      for (const Vec3& x : pts[g]) {
        Vec3 nrm = all.sign[g] * (c - x);  // eq. (2): outward normal
        const double len = nrm.norm();
        nrm = len > 0 ? Vec3(nrm / len) : Vec3(1, 0, 0);
        out->points.P.row(k) = frame.FromUnit(x).transpose();
        out->points.N.row(k) = nrm.transpose();
        out->sample[k] = all.sample[g];
        ++k;
      }
    }
  };

  // All spheres in one tree: the final check's, and the containment cache's.
  // A point that stays where it is from one iteration to the next (a tangent
  // sphere keeps its points) is tested against each new batch; the list of
  // all balls containing it by more than tol, collected once, answers every
  // batch by lookup (a batch is a subset of all spheres). Per sphere: its
  // points as MakeFeasible last tested them, each listed the second time it
  // is tested there (on thin shapes most kept points move within two
  // iterations, and a list for each cost more than it saved: eiffel n = 40
  // 54 % of first sightings never came back), and only while batches are
  // not too small a part of all spheres (list_kept below).
  const SphereTree full(all.centers, all.radii, ids);
  struct Known {
    Vec3 at;
    bool listed = false;
    std::vector<int> inside;  // listed: the spheres containing `at` by more than tol
  };
  std::vector<std::vector<Known>> known(ns);
  std::vector<char> in_batch(ns, 0);

  FineTuneResult result;
  Rng rng = ctx.MakeRng("fine_tune.batch");
  for (int it = 0; it < options.iterations; ++it) {
    ctx.CheckStop();
    FineTuneIteration stats;
    // 1. Reconstruct from the current points.
    auto t0 = Clock::now();
    FineTuneResult current;
    to_cloud(&current);
    std::unique_ptr<TuningSurface> omega;
    try {
      omega = reconstruct(current.points, frame);
    } catch (const Cancelled&) {
      throw;
    } catch (const std::exception& e) {
      result.stopped_early = true;
      result.stop_reason = std::string("reconstruction failed at iteration ") + std::to_string(it + 1) + ": " + e.what();
      ctx.Warn("fine_tune: " + result.stop_reason + "; keeping the points of the previous iteration");
      break;
    }
    if (!omega) {
      result.stopped_early = true;
      result.stop_reason = "empty reconstruction at iteration " + std::to_string(it + 1);
      ctx.Warn("fine_tune: " + result.stop_reason + "; keeping the points of the previous iteration");
      break;
    }
    stats.reconstruct_s = Since(t0);

    // 2. Closest points and inside/outside of every sphere centre.
    t0 = Clock::now();
    omega->Prepare();
    const TuningSurface& surface = *omega;
    VectorXd sqd, w;
    MatrixX3d cp;
    surface.ClosestPointsAndWindingNumbers(all.centers, &sqd, &cp, &w);
    stats.query_s = Since(t0);

    // 3. The constraint batch (both signs), drawn without replacement.
    t0 = Clock::now();
    const std::vector<int> batch = DrawBatch(ns, options.batch_size, rng);
    const SphereTree tree(all.centers, all.radii, ids, &batch);
    // Lists only while the batch holds at least 1/20 of all spheres: a
    // list is one query of the full tree, a batch query one of a tree 1/f
    // times sparser, so at small f the lists cost more than they save
    // (bunny, k_max 10, n_max 3: n = 50, f = 0.08, even; n = 70, f = 0.03,
    // 3 s less without; n = 100, f = 0.01, 202 -> 178 s).
    const bool list_kept = 20 * static_cast<std::int64_t>(batch.size()) >= ns;
    std::fill(in_batch.begin(), in_batch.end(), 0);
    for (int b : batch) in_batch[b] = 1;

    // 4. Per sphere: move, add, second chance, make feasible.
    std::vector<std::vector<Vec3>> next(ns);
    std::vector<signed char> kind(ns, 0);  // 1 intersected, 2 too far, 3 tangent
    std::vector<char> second(ns, 0);
    std::vector<int> dropped(ns, 0);
    ParallelFor(ns, [&](std::int64_t begin, std::int64_t end) {
      SphereTree::LocalSet local_set;
      for (std::int64_t gi = begin; gi < end; ++gi) {
        const int g = static_cast<int>(gi);
        if (!all.wants_point[g]) continue;
        const Vec3 c = all.centers.row(g).transpose();
        const double r = all.radii[g];
        const SphereTree::LocalSet* local = LocalFor(tree, c, r, local_radius, options.search.tol, &local_set);
        const double d = std::sqrt(sqd[g]);
        // proj_onto(): the side flips when the surface puts the centre on the wrong side.
        const double sigma = (all.sign[g] < 0 ? -1.0 : 1.0) * (w[g] > 0.5 ? -1.0 : 1.0);
        auto project = [&](const Vec3& target) {
          Vec3 dir = target - c;
          const double len = dir.norm();
          if (len < 1e-300) return Vec3(c + Vec3(r, 0, 0));
          return Vec3(c + sigma * r * dir / len);
        };
        const Vec3 q = project(cp.row(g).transpose());
        std::vector<Vec3>& mine = pts[g];
        // The sphere's candidate points, each with whether Transport has
        // just found it feasible (Alg. 2 then need not test it again).
        struct Candidate {
          Vec3 x;
          bool tested;
          bool kept = false;  // a point of the last iteration, unmoved
        };
        std::vector<Candidate> cand;
        auto keep_all = [&]() {
          for (const Vec3& a : mine) cand.push_back({a, false, true});
        };
        auto closest_to = [&](const Vec3& target) {
          size_t best = 0;
          for (size_t k = 1; k < mine.size(); ++k)
            if ((mine[k] - target).squaredNorm() < (mine[best] - target).squaredNorm()) best = k;
          return best;
        };
        auto transport = [&](const Vec3& p, const Vec3& target, bool* ok) {
          return Transport(p, target, c, r, options.tau, options.halvings, tree, options.search.tol, g,
                           options.jump_when_blocked, local, samples.dim, ok);
        };
        // A sphere without a point gets q if feasible ("second chance");
        // otherwise its point closest to q moves towards q. Returns that
        // point's index, or mine.size() for a second chance.
        auto second_chance_or_move_closest = [&]() -> size_t {
          if (mine.empty()) {
            cand.push_back({q, false});
            second[g] = 1;
            return 0;
          }
          const size_t k0 = closest_to(q);
          bool ok = false;
          const Vec3 x = transport(mine[k0], q, &ok);
          cand.push_back({x, ok});
          return k0;
        };
        if (r <= options.search.tol) {
          kind[g] = 3;
          keep_all();
        } else if (d < r - options.search.tol) {  // the surface cuts into the sphere
          kind[g] = 1;
          second_chance_or_move_closest();
          if (!mine.empty()) {
            if (options.max_points_per_sphere > 1) {
              // Every existing point moves towards the projection of its own
              // closest surface point; ordered by distance to the surface.
              std::vector<std::pair<double, Candidate>> moved;
              const Vec3 cpg = cp.row(g).transpose();  // on the surface: bounds each point's distance
              for (const Vec3& a : mine) {
                Vec3 hp;
                const double hd = surface.Closest(a, &hp, (a - cpg).squaredNorm());
                bool ok = false;
                const Vec3 x = transport(a, project(hp), &ok);
                moved.push_back({hd, {x, ok}});
              }
              std::stable_sort(moved.begin(), moved.end(),
                               [](const auto& x, const auto& y) { return x.first < y.first; });
              // Severe cut (|t| < 4/5 |s|): one more point (up to n_max);
              // otherwise the point farthest from the surface is discarded.
              const bool severe = d < options.severe_ratio * r;
              size_t keep = severe ? moved.size() : moved.size() - 1;
              keep = std::min<size_t>(keep, static_cast<size_t>(options.max_points_per_sphere - 1));
              for (size_t k = 0; k < keep; ++k) cand.push_back(moved[k].second);
            }
          }
        } else if (d > r + options.search.tol) {  // the surface misses the sphere
          kind[g] = 2;
          const size_t k0 = second_chance_or_move_closest();
          if (!mine.empty()) {
            if (options.keep_points_when_missed)
              for (size_t k = 0; k < mine.size(); ++k)
                if (k != k0) cand.push_back({mine[k], false, true});
          }
        } else {  // tangent: keep
          kind[g] = 3;
          keep_all();
          if (cand.empty()) {
            cand.push_back({q, false});
            second[g] = 1;
          }
        }
        // Algorithm 2 against the batch of both signs; infeasible ones go.
        // A kept point's first test is answered from its containment list.
        std::vector<Vec3>& out = next[g];
        std::vector<Known> known_next;
        for (const Candidate& cd : cand) {
          Vec3 x = cd.x;
          KnownContainment kc;
          const KnownContainment* kp = nullptr;
          Known* entry = nullptr;
          if (cd.tested) {
            kc = {cd.x, false};
            kp = &kc;
          } else if (cd.kept) {
            const Vec3 at = OntoSphere(c, r, cd.x);
            for (Known& e : known[g])
              if (e.at == at) entry = &e;
            if (!entry && list_kept) {
              known[g].push_back({at, false, {}});  // first sighting: the batch query
              entry = &known[g].back();
            } else if (entry) {
              if (!entry->listed) {
                full.CollectContaining(at, -options.search.tol, g, &entry->inside);
                entry->listed = true;
              }
              kc.at = at;
              for (int s : entry->inside) kc.contained = kc.contained || in_batch[s];
              kp = &kc;
            }
          }
          if (MakeFeasible(tree, c, r, g, mf, &x, nullptr, local, kp)) {
            out.push_back(x);
            if (entry && x == entry->at) known_next.push_back(*entry);
          } else {
            ++dropped[g];
          }
        }
        known[g].swap(known_next);
        if (out.empty()) second[g] = 0;
      }
    }, 64);
    pts.swap(next);
    for (int g = 0; g < ns; ++g) {
      stats.intersected += kind[g] == 1;
      stats.too_far += kind[g] == 2;
      stats.tangent += kind[g] == 3;
      stats.second_chance += second[g];
      stats.dropped += dropped[g];
      stats.points += static_cast<std::int64_t>(pts[g].size());
    }
    stats.update_s = Since(t0);
    result.iterations.push_back(stats);
    ctx.Info("fine_tune: iteration " + std::to_string(it + 1) + ": " + std::to_string(stats.points) + " points, " +
             std::to_string(stats.intersected) + " intersected, " + std::to_string(stats.too_far) + " too far, " +
             std::to_string(stats.tangent) + " tangent, " + std::to_string(stats.dropped) + " dropped");
    ctx.Progress(static_cast<double>(it + 1) / options.iterations, "fine-tuning");
  }
  // The final check against all spheres (issue 10, criterion 4), measured in
  // every mode: kOff counts the violators and keeps them.
  {
    ctx.CheckStop();
    const auto t0 = Clock::now();
    const FineTuneOptions::FinalCheck mode = options.final_check;
    const double tol = options.search.tol;
    std::vector<int> before(ns, 0), repaired(ns, 0), removed(ns, 0), after(ns, 0);
    ParallelFor(ns, [&](std::int64_t begin, std::int64_t end) {
      SphereTree::LocalSet local_set;
      for (std::int64_t gi = begin; gi < end; ++gi) {
        const int g = static_cast<int>(gi);
        if (pts[g].empty()) continue;
        const Vec3 c = all.centers.row(g).transpose();
        const double r = all.radii[g];
        const SphereTree::LocalSet* local = LocalFor(full, c, r, local_radius, tol, &local_set);
        // A point with a containment list (all spheres) needs no query.
        auto contained = [&](const Vec3& x) {
          for (const Known& e : known[g])
            if (e.listed && e.at == x) return !e.inside.empty();
          return full.AnyContains(x, -tol, g, local);
        };
        // Every point is tested once; what the result still violates is
        // counted as it is kept (a point kept unmoved keeps its answer, and a
        // repaired one is kept only after its own test), so no second pass
        // asks the tree again.
        std::vector<Vec3> keep;
        keep.reserve(pts[g].size());
        for (Vec3 x : pts[g]) {
          if (!contained(x)) {
            keep.push_back(x);
            continue;
          }
          ++before[g];
          if (mode == FineTuneOptions::FinalCheck::kOff) {
            keep.push_back(x);
            ++after[g];
            continue;
          }
          // Algorithm 2 starts from the containment just found (the same
          // answer as its own first query, which it then skips).
          // When its last test was the query below, at the same point, its
          // answer stands.
          const KnownContainment known_inside{x, true};
          bool free_at_end = false;
          if (mode == FineTuneOptions::FinalCheck::kRepair &&
              MakeFeasible(full, c, r, g, mf, &x, nullptr, local, &known_inside, &free_at_end) &&
              (free_at_end || !full.AnyContains(x, -tol, g, local))) {
            keep.push_back(x);
            ++repaired[g];
          } else {
            ++removed[g];
          }
        }
        pts[g].swap(keep);
      }
    }, 64);
    for (int g = 0; g < ns; ++g) {
      result.final_infeasible_before += before[g];
      result.final_repaired += repaired[g];
      result.final_dropped += removed[g];
      result.final_infeasible += after[g];
    }
    result.final_check_s = Since(t0);
    ctx.Info("fine_tune: final check (" + EnumToName(FineTuneOptions::kFinalCheckNames, mode) + ") against all " +
             std::to_string(ns) + " spheres: " + std::to_string(result.final_infeasible_before) +
             " points inside another sphere by more than tol, " + std::to_string(result.final_repaired) +
             " repaired, " + std::to_string(result.final_dropped) + " dropped, " +
             std::to_string(result.final_infeasible) + " left");
  }
  to_cloud(&result);
  return result;
}

}  // namespace arcs
