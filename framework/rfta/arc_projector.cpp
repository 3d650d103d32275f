#include "framework/rfta/arc_projector.h"

#include "framework/error.h"
#include "framework/rfta/trilateration.h"
#include "framework/spatial/knn.h"
#include "framework/util/parallel.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

namespace arcs {
namespace {

using namespace trilateration;

// A unit vector perpendicular to u (in the plane z = 0 for dim 2).
Vec3 AnyPerpendicular(const Vec3& u, int dim) {
  if (dim == 2) return Vec3(-u.y(), u.x(), 0.0);
  int a = 0;
  for (int k = 1; k < 3; ++k)
    if (std::abs(u[k]) < std::abs(u[a])) a = k;
  return u.cross(Vec3::Unit(a)).normalized();
}

// Points of the intersection of spheres (ci, ri) and (cj, rj) near x. In 3D
// the intersection is a circle and out[0] is its closest point to x; in 2D it
// is two points (both returned). Spheres that do not intersect give their
// point of closest approach: externally apart -> ci + ri u (toward cj);
// sphere i inside j -> ci - ri u (the point least inside j); j inside i ->
// ci + ri u. Returns the number of points (0 for concentric spheres).
int SphereSpherePoints(const Vec3& ci, double ri, const Vec3& cj, double rj, const Vec3& x, int dim,
                       Vec3 out[2]) {
  const Vec3 d = cj - ci;
  const double dist = d.norm();
  if (!(dist > 1e-14 * std::max(ri, rj))) return 0;
  const Vec3 u = d / dist;
  if (dist >= ri + rj) {
    out[0] = ci + ri * u;
    return 1;
  }
  if (dist <= std::abs(ri - rj)) {
    out[0] = rj > ri ? Vec3(ci - ri * u) : Vec3(ci + ri * u);
    return 1;
  }
  const double a = (dist * dist + ri * ri - rj * rj) / (2.0 * dist);  // c_i to the circle's plane
  const double h = std::sqrt(std::max(0.0, ri * ri - a * a));          // circle radius
  const Vec3 m = ci + a * u;
  if (dim == 2) {
    const Vec3 w = AnyPerpendicular(u, 2);
    out[0] = m + h * w;
    out[1] = m - h * w;
    return 2;
  }
  Vec3 v = x - m;
  v -= v.dot(u) * u;
  const double vn = v.norm();
  const Vec3 w = vn > 1e-14 * ri ? Vec3(v / vn) : AnyPerpendicular(u, 3);
  out[0] = m + h * w;
  return 1;
}

// Whether |v| < R, decided as (v.norm() < R) decides it: norm() is the
// correctly rounded square root of squaredNorm(), so away from R^2 the
// squares give the same answer without the root (relative margin 1e-12,
// far above the few roundings of R^2; tiny R^2 takes the root).
inline bool NormBelow(const Vec3& v, double R) {
  const double d2 = v.squaredNorm(), R2 = R * R;
  if (R > 0.0 && R2 > 1e-280 && R2 < 1e280) {
    if (d2 > R2 * (1.0 + 1e-12)) return false;
    if (d2 < R2 * (1.0 - 1e-12)) return true;
  }
  return std::sqrt(d2) < R;
}

// Points per chunk sharing one local constraint list, and the chunk box's
// margin and largest diagonal, in sample spacings 1 / N^(1/d) (tuned on the
// torus at n = 20, 40, 100).
constexpr std::int64_t kChunk = 16;
constexpr double kLocalMargin = 0.25;
constexpr double kLocalMaxDiagonal = 4.0;

// Indices of the rows of P in Morton (Z-curve) order on [0,1]^3, 21 bits per
// axis; ties by index.
std::vector<std::int64_t> ZOrder(const MatrixX3d& P) {
  auto spread = [](std::uint64_t v) {
    v &= 0x1fffff;
    v = (v | v << 32) & 0x1f00000000ffffull;
    v = (v | v << 16) & 0x1f0000ff0000ffull;
    v = (v | v << 8) & 0x100f00f00f00f00full;
    v = (v | v << 4) & 0x10c30c30c30c30c3ull;
    v = (v | v << 2) & 0x1249249249249249ull;
    return v;
  };
  const std::int64_t n = P.rows();
  std::vector<std::pair<std::uint64_t, std::int64_t>> key(n);
  ParallelFor(
      n,
      [&](std::int64_t begin, std::int64_t end) {
        for (std::int64_t i = begin; i < end; ++i) {
          std::uint64_t code = 0;
          for (int a = 0; a < 3; ++a) {
            const double v = std::clamp(P(i, a), 0.0, 1.0) * 2097151.0;
            code |= spread(static_cast<std::uint64_t>(v)) << a;
          }
          key[i] = {code, i};
        }
      },
      4096);
  std::sort(key.begin(), key.end());
  std::vector<std::int64_t> order(n);
  for (std::int64_t i = 0; i < n; ++i) order[i] = key[i].second;
  return order;
}

}  // namespace

void MakeFeasibleOptions::Check() const {
  ARCS_CHECK_OPTION(dim == 2 || dim == 3, "dim", dim, "2 or 3");
  ARCS_CHECK_OPTION(iterations >= 0, "iterations", iterations, ">= 0");
  ARCS_CHECK_OPTION(k_search >= 1, "k_search", k_search, ">= 1");
  ARCS_CHECK_OPTION(tol >= 0.0 && tol < 0.1, "tol", tol, "in [0, 0.1)");
}

bool MakeFeasible(const SphereTree& tree, const Vec3& c, double r, int self_id, const MakeFeasibleOptions& o,
                  Vec3* x, int* steps, const SphereTree::LocalSet* local, const KnownContainment* known,
                  bool* free_at_end) {
  auto on_sphere = [&](const Vec3& v) { return OntoSphere(c, r, v); };
  auto center = [&](int k) {
    const SphereTree::Ball& b = tree.ball(k);
    return Vec3(b.x, b.y, b.z);
  };
  // One traversal answers both questions: the balls with |x - c| - r < tol,
  // deepest first, and whether the deepest contains x by more than tol.
  thread_local std::vector<int> found;
  auto gather = [&]() {
    tree.DeepestContaining(*x, o.tol, o.k_search, self_id, &found, local);
    return found.empty() || (*x - center(found[0])).norm() - tree.ball(found[0]).r >= -o.tol;
  };
  // Admissible candidate: inside the unit box (+- tol) unless exempt, and not
  // inside a gathered ball other than the ones it was built on by more than tol.
  auto admissible = [&](const Vec3& v, int skip1, int skip2, bool box_check) {
    if (box_check) {
      for (int a = 0; a < o.dim; ++a)
        if (v[a] < -o.tol || v[a] > 1.0 + o.tol) return false;
    }
    for (int k : found) {
      if (k == skip1 || k == skip2) continue;
      if (NormBelow(v - center(k), tree.ball(k).r - o.tol)) return false;
    }
    return true;
  };
  struct Candidate {
    double d;  // distance to x
    int order;  // generation order (ties)
    int skip1, skip2;
    bool box_check;
    Vec3 v;
  };
  thread_local std::vector<Candidate> cands;

  // Most points given are feasible already: the early-exit containment test
  // settles those without gathering (the same answer as gather()'s).
  // `clear`: whether the last answer was AnyContains' "no" at *x.
  bool clear = false;
  auto check = [&]() {
    clear = !tree.AnyContains(*x, -o.tol, self_id, local);
    return clear || gather();
  };
  *x = on_sphere(*x);
  int step = 0;
  bool feasible;
  if (known && *x == known->at) {
    if (!known->contained) {
      if (steps) *steps = 0;
      if (free_at_end) *free_at_end = true;
      return true;
    }
    feasible = gather();
  } else {
    feasible = check();
  }
  while (!feasible && step < o.iterations) {
    // Official order: by radius, ascending (ties by id).
    std::sort(found.begin(), found.end(), [&](int a, int b) {
      const double ra = tree.ball(a).r, rb = tree.ball(b).r;
      return ra < rb || (ra == rb && tree.id(a) < tree.id(b));
    });
    cands.clear();
    auto add = [&](const Vec3& v, int skip1, int skip2, bool box_check) {
      cands.push_back({(v - *x).norm(), static_cast<int>(cands.size()), skip1, skip2, box_check, v});
    };
    Vec3 pts[2];
    const int m = static_cast<int>(found.size());
    bool have = false;
    Vec3 best = *x;
    if (o.dim == 2) {
      // Paper Alg. 2, d = 2: intersections of the circle with each gathered one.
      for (int k : found) {
        const int n = SphereSpherePoints(c, r, center(k), tree.ball(k).r, *x, 2, pts);
        for (int t = 0; t < n; ++t) add(pts[t], k, -1, true);
      }
    } else if (m == 1) {
      // One neighbour: the closest point of the circle S_i ∩ S_j (official: no box check).
      if (SphereSpherePoints(c, r, center(found[0]), tree.ball(found[0]).r, *x, 3, pts) > 0)
        add(pts[0], found[0], -1, false);
    } else if (o.pair_choice == PairChoice::kClosest) {
      // The closest admissible point among the circle points q_a (closest
      // point of S_i ∩ S_a to x) and the triple points of S_i, S_a, S_b.
      // A triple point lies on both circles, so it is at least
      // max(|q_a - x|, |q_b - x|) from x: visiting the balls by increasing
      // |q - x| and stopping once that exceeds the best admissible distance
      // finds the closest without trilaterating every pair.
      thread_local std::vector<std::pair<double, int>> near;  // (|q_a - x|, position in found)
      thread_local std::vector<Vec3> q;
      near.clear();
      q.resize(m);
      for (int t = 0; t < m; ++t) {
        const int n = SphereSpherePoints(c, r, center(found[t]), tree.ball(found[t]).r, *x, 3, pts);
        if (n == 0) continue;  // concentric: no circle
        q[t] = pts[0];
        near.push_back({(pts[0] - *x).norm(), t});
      }
      std::sort(near.begin(), near.end());
      double best_d = std::numeric_limits<double>::infinity();
      double best_d2 = best_d;  // the square best_d is the root of
      auto offer = [&](const Vec3& v, int skip1, int skip2) {
        // norm() is the rounded root of the squared norm, and rounding is
        // monotone: no square at or above best_d2 has a root below best_d.
        const double d2 = (v - *x).squaredNorm();
        if (!(d2 < best_d2)) return;
        const double d = std::sqrt(d2);
        if (d < best_d && admissible(v, skip1, skip2, true)) {
          best_d = d;
          best_d2 = d2;
          best = v;
          have = true;
        }
      };
      // Each ball's trilateration frame with the sphere, made once (the
      // balls visited so far, in `near` order).
      thread_local std::vector<TrilaterationBase> base;
      base.clear();
      for (std::size_t bi = 0; bi < near.size(); ++bi) {
        if (near[bi].first >= best_d) break;
        const int kb = found[near[bi].second];
        offer(q[near[bi].second], kb, -1);
        const Vec3 cb = center(kb);
        const double rb = tree.ball(kb).r;
        // Two pairs at a time, offered in the same order as one by one.
        std::size_t ai = 0;
        for (; ai + 2 <= bi; ai += 2) {
          const int ka[2] = {found[near[ai].second], found[near[ai + 1].second]};
          const TrilaterationBase* const bases[2] = {&base[ai], &base[ai + 1]};
          const double ra[2] = {tree.ball(ka[0]).r, tree.ball(ka[1]).r};
          Vec3 two[2][2];
          int n2[2];
          TrilaterateWith2(bases, c, r, ra, cb, rb, two, n2);
          for (int k = 0; k < 2; ++k)
            for (int t = 0; t < n2[k]; ++t) offer(two[k][t], ka[k], kb);
        }
        for (; ai < bi; ++ai) {
          const int ka = found[near[ai].second];
          const int n = TrilaterateWith(base[ai], c, r, tree.ball(ka).r, cb, rb, pts);
          for (int t = 0; t < n; ++t) offer(pts[t], ka, kb);
        }
        base.push_back(TrilaterateBase(c, r, cb, rb));
      }
    } else {
      for (int a = 0; a < m && !have; ++a)
        for (int b = a + 1; b < m && !have; ++b) {
          const std::size_t first = cands.size();
          const int ka = found[a], kb = found[b];
          const int n = Trilaterate(c, r, center(ka), tree.ball(ka).r, center(kb), tree.ball(kb).r, pts);
          if (n > 0) {
            for (int t = 0; t < n; ++t) add(pts[t], ka, kb, true);
          } else {
            // Trilateration failed: the two circle points (official: no box check).
            if (SphereSpherePoints(c, r, center(ka), tree.ball(ka).r, *x, 3, pts) > 0) add(pts[0], ka, -1, false);
            if (SphereSpherePoints(c, r, center(kb), tree.ball(kb).r, *x, 3, pts) > 0) add(pts[0], kb, -1, false);
          }
          // Official: the first pair with an admissible candidate, the
          // closer of its candidates.
          double bd = std::numeric_limits<double>::infinity();
          for (std::size_t t = first; t < cands.size(); ++t) {
            const Candidate& cd = cands[t];
            if (cd.d < bd && admissible(cd.v, cd.skip1, cd.skip2, cd.box_check)) {
              bd = cd.d;
              best = cd.v;
              have = true;
            }
          }
        }
    }
    if (!have && (o.dim == 2 || m == 1)) {
      // The closest admissible candidate (paper Alg. 2 line 13): test in
      // order of distance, stop at the first admissible one.
      std::sort(cands.begin(), cands.end(), [](const Candidate& a, const Candidate& b) {
        return a.d < b.d || (a.d == b.d && a.order < b.order);
      });
      for (const Candidate& q : cands) {
        if (admissible(q.v, q.skip1, q.skip2, q.box_check)) {
          best = q.v;
          have = true;
          break;
        }
      }
    }
    if (!have) break;  // nothing admissible: x stays
    const Vec3 next = on_sphere(best);
    if (next == *x) break;
    *x = next;
    ++step;
    feasible = check();
  }
  if (steps) *steps = step;
  if (free_at_end) *free_at_end = feasible && clear;
  return feasible;
}

std::vector<int> DrawBatch(std::int64_t n, std::int64_t b, Rng& rng) {
  std::vector<int> idx(static_cast<std::size_t>(std::max<std::int64_t>(n, 0)));
  std::iota(idx.begin(), idx.end(), 0);
  if (b <= 0 || n <= b) return idx;
  // Partial Fisher–Yates: the first b entries are a uniform b-subset.
  for (std::int64_t t = 0; t < b; ++t) {
    const std::int64_t j = t + static_cast<std::int64_t>(rng.UniformInt(static_cast<std::uint64_t>(n - t)));
    std::swap(idx[t], idx[j]);
  }
  idx.resize(b);
  std::sort(idx.begin(), idx.end());
  return idx;
}

void FeasibleSearchOptions::Check() const {
  ARCS_CHECK_OPTION(local_search_iters >= 0 && local_search_iters <= 10000, "local_search_iters",
                    local_search_iters, "in [0, 10000]");
  ARCS_CHECK_OPTION(local_searches >= 0 && local_searches <= 100000, "local_searches", local_searches,
                    "in [0, 100000] (0 = ceil(2 N^(1/d)))");
  ARCS_CHECK_OPTION(tol >= 0.0 && tol < 0.1, "tol", tol, "in [0, 0.1)");
}

void ArcProjectorOptions::Check() const {
  search.Check();
  ARCS_CHECK_OPTION(batch_size >= 0, "batch_size", batch_size, ">= 0 (0 = all spheres)");
  SignSplitOptions{zero_radius}.Check();
}

ArcProjection ProjectToArcs(const SdfSamples& samples, const FreeSpaceSamples& free,
                            const ArcProjectorOptions& o, const Context& ctx) {
  o.Check();
  CheckRftaSamples(samples, "arc_projector");
  if (!free.sign.empty() && static_cast<std::int64_t>(free.sign.size()) != free.Size())
    throw Error("arc_projector: " + std::to_string(free.sign.size()) + " free-point signs for " +
                std::to_string(free.Size()) + " free points");
  const SignedSpheres sp = SplitSpheresBySign(samples, SignSplitOptions{o.zero_radius});
  RequireBothSigns(sp, "arc_projector");
  const int dim = samples.dim;
  ArcProjection result;
  ArcProjectorStats& st = result.stats;
  st.zero = sp.num_zero;
  st.k_search = o.search.local_searches > 0 ? o.search.local_searches : LocalSearchHeuristic(sp.num_samples, dim);
  MakeFeasibleOptions mf;
  mf.dim = dim;
  mf.iterations = o.search.local_search_iters;
  mf.k_search = st.k_search;
  mf.tol = o.search.tol;
  mf.pair_choice = o.search.pair_choice;
  mf.Check();

  // Per sample: the unit-frame point, and its fate (0 none, 1 feasible at
  // projection, 2 made feasible, 3 dropped).
  const std::int64_t N = samples.Size();
  MatrixX3d point(N, 3);
  std::vector<std::uint8_t> fate(N, 0);
  Rng batch_rng = ctx.MakeRng("arc_projector/batch");
  int signs_without_free = 0;
  for (int si = 0; si < 2; ++si) {
    const int sign = si == 0 ? 1 : -1;
    const SphereSet& set = sp.Get(sign);
    const char* name = sign > 0 ? "positive" : "negative";
    // Free points of this sign, in the unit frame.
    std::int64_t nf = 0;
    for (std::int64_t j = 0; j < free.Size(); ++j) nf += free.sign.empty() || free.sign[j] == sign;
    MatrixX3d F(nf, 3);
    for (std::int64_t j = 0, w = 0; j < free.Size(); ++j) {
      if (!free.sign.empty() && free.sign[j] != sign) continue;
      Vec3 u = sp.frame.ToUnit(free.points.row(j).transpose());
      if (dim == 2) u.z() = 0.0;
      if (!u.allFinite()) throw Error("arc_projector: free point " + std::to_string(j) + " is not finite");
      F.row(w++) = u.transpose();
    }
    if (nf == 0) {
      // A coarse grid of a thin shape can leave one sign's spheres without
      // any free cell: they get no initial point here (fine-tuning gives them
      // a second chance); only when both signs have none is it an error.
      if (set.Size() > 0) {
        ++signs_without_free;
        ctx.Warn(std::string("arc_projector: no free-space samples for the ") + name +
                 " spheres; they start without tangency points");
      }
      continue;
    }
    const std::vector<int> members = DrawBatch(set.Size(), o.batch_size, batch_rng);
    st.batch[si] = static_cast<std::int64_t>(members.size());
    const SphereTree tree(set.centers, set.radii, set.sample, &members);
    std::vector<int> want;
    for (int i = 0; i < set.Size(); ++i) {
      if (set.wants_point[i]) want.push_back(i);
      else ++st.clamped;
    }
    const std::int64_t nw = static_cast<std::int64_t>(want.size());
    MatrixX3d Q(nw, 3);
    for (std::int64_t t = 0; t < nw; ++t) Q.row(t) = set.centers.row(want[t]);
    Eigen::VectorXi nearest;
    {
      const KdTree3 kd(F);
      kd.NearestBatch(Q, &nearest, nullptr);
    }
    // Project the closest free point onto each sphere (Alg. 1 line 6).
    MatrixX3d X(nw, 3);
    ParallelFor(
        nw,
        [&](std::int64_t begin, std::int64_t end) {
          for (std::int64_t t = begin; t < end; ++t) {
            const Vec3 c = Q.row(t).transpose();
            const Vec3 d = F.row(nearest[t]).transpose() - c;
            const double n = d.norm();
            const double r = set.radii[want[t]];
            X.row(t) = (n > 0.0 ? Vec3(c + (r / n) * d) : Vec3(c + r * Vec3::UnitX())).transpose();
          }
        },
        4096);
    // Make feasible (Alg. 2) in chunks of nearby points (Morton order of the
    // projections): each chunk scans one short list of nearby constraint
    // balls instead of traversing the tree per query (same results).
    const std::vector<std::int64_t> order = ZOrder(X);
    const double spacing = 1.0 / SamplesPerAxis(sp.num_samples, dim);
    const std::int64_t nchunks = (nw + kChunk - 1) / kChunk;
    ParallelFor(
        nchunks,
        [&](std::int64_t begin, std::int64_t end) {
          SphereTree::LocalSet local;
          for (std::int64_t ch = begin; ch < end; ++ch) {
            const std::int64_t t0 = ch * kChunk, t1 = std::min(nw, t0 + kChunk);
            Vec3 lo = X.row(order[t0]).transpose(), hi = lo;
            for (std::int64_t u = t0 + 1; u < t1; ++u) {
              lo = lo.cwiseMin(X.row(order[u]).transpose());
              hi = hi.cwiseMax(X.row(order[u]).transpose());
            }
            // Room for the moves of Alg. 2; a point that leaves the box
            // queries the tree. Chunks spread far (a Morton jump) skip it.
            lo.array() -= kLocalMargin * spacing;
            hi.array() += kLocalMargin * spacing;
            const bool use_local = (hi - lo).norm() <= kLocalMaxDiagonal * spacing;
            if (use_local) tree.CollectLocal(lo, hi, mf.tol, &local);
            for (std::int64_t u = t0; u < t1; ++u) {
              const std::int64_t t = order[u];
              const int i = want[t];
              Vec3 x = X.row(t).transpose();
              int steps = 0;
              const bool ok = MakeFeasible(tree, Q.row(t).transpose(), set.radii[i], set.sample[i], mf, &x,
                                           &steps, use_local ? &local : nullptr);
              const int s = set.sample[i];
              point.row(s) = x.transpose();
              fate[s] = ok ? (steps == 0 ? 1 : 2) : 3;
            }
          }
        },
        8);
    ctx.CheckStop();
  }
  if (signs_without_free == 2)
    throw Error("arc_projector: the empty-space sampler found no free-space samples for either sign");

  std::int64_t count = 0;
  for (std::int64_t s = 0; s < N; ++s) {
    st.spheres += fate[s] != 0;
    st.feasible_at_projection += fate[s] == 1;
    st.made_feasible += fate[s] == 2;
    st.dropped += fate[s] == 3;
    count += fate[s] == 1 || fate[s] == 2;
  }
  result.points.P.resize(count, 3);
  result.points.N.resize(count, 3);
  result.sample.reserve(count);
  for (std::int64_t s = 0, w = 0; s < N; ++s) {
    if (fate[s] != 1 && fate[s] != 2) continue;
    // Back to the input frame, exactly on the sample's sphere of radius |s|.
    const Vec3 p = SamplePoint(samples, s);
    const double rad = std::abs(samples.values[s]);
    Vec3 x = sp.frame.FromUnit(point.row(s).transpose());
    if (dim == 2) x.z() = 0.0;
    Vec3 d = x - p;
    const double dn = d.norm();
    d = dn > 0.0 ? Vec3(d / dn) : Vec3::UnitX();
    x = p + rad * d;
    // Eq. (2): n = sign(s) (p - a) / |p - a|: toward the centre of an outside
    // sphere, away from the centre of an inside one — out of the shape.
    const Vec3 nrm = samples.values[s] > 0 ? Vec3(-d) : d;
    result.points.P.row(w) = x.transpose();
    result.points.N.row(w) = nrm.transpose();
    result.sample.push_back(static_cast<int>(s));
    ++w;
  }
  return result;
}

}  // namespace arcs
