// Ball BVH: median splits on the longest axis of the centres' box, leaves of
// up to kLeafSize balls stored contiguously. The node layout is depth-first
// (left child = next node), and the subtree sizes are known from the ball
// counts alone, so both halves are built in parallel into one array.
#include "framework/rfta/sphere_tree.h"

#include "framework/error.h"

#include <Eigen/Cholesky>

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <utility>

namespace arcs {
namespace {

constexpr std::int32_t kLeafSize = 32;
constexpr std::int32_t kParallelBuild = 1 << 14;  // build halves in parallel above this
constexpr int kStack = 96;                        // > depth of a median-split tree of 2^31 balls

// Leaves(m) of a median-split tree of m balls: a ball count splits into
// floor(m/2) and ceil(m/2), so Leaves(m) and Leaves(m+1) depend only on
// Leaves(floor(m/2)) and Leaves(floor(m/2) + 1). Returns both.
std::pair<std::int64_t, std::int64_t> LeavesPair(std::int64_t m) {
  if (m + 1 <= kLeafSize) return {1, 1};
  const std::int64_t h = m / 2;
  const auto [a, b] = LeavesPair(h);  // Leaves(h), Leaves(h + 1)
  auto leaves = [&](std::int64_t n) -> std::int64_t {
    if (n <= kLeafSize) return 1;
    const std::int64_t lo = n / 2, hi = n - n / 2;  // both in {h, h + 1}
    return (lo == h ? a : b) + (hi == h ? a : b);
  };
  return {leaves(m), leaves(m + 1)};
}

inline double Sq(double v) { return v * v; }

}  // namespace

std::int32_t SphereTree::NodeCount(std::int32_t n) {
  if (n <= 0) return 0;
  return static_cast<std::int32_t>(2 * LeavesPair(n).first - 1);
}

SphereTree::SphereTree(const MatrixX3d& centers, const VectorXd& radii, const std::vector<int>& ids,
                       const std::vector<int>* members) {
  std::vector<std::int32_t> order;
  if (members) {
    order.assign(members->begin(), members->end());
  } else {
    order.resize(radii.size());
    for (std::int32_t i = 0; i < static_cast<std::int32_t>(order.size()); ++i) order[i] = i;
  }
  const std::int32_t n = static_cast<std::int32_t>(order.size());
  for (std::int32_t i : order) {
    if (i < 0 || i >= radii.size() || i >= static_cast<std::int64_t>(ids.size()) || i >= centers.rows())
      throw Error("SphereTree: member index out of range");
  }
  if (n == 0) return;
  nodes_.resize(NodeCount(n));
  Build(order, 0, n, 0, centers, radii);
  balls_.resize(n);
  ids_.resize(n);
  for (std::int32_t k = 0; k < n; ++k) {
    const std::int32_t i = order[k];
    balls_[k] = {centers(i, 0), centers(i, 1), centers(i, 2), radii[i]};
    ids_[k] = ids[i];
  }
}

void SphereTree::Build(std::vector<std::int32_t>& order, std::int32_t begin, std::int32_t end,
                               std::int32_t ni, const MatrixX3d& C, const VectorXd& R) {
  Node& node = nodes_[ni];
  for (int a = 0; a < 3; ++a) {
    node.lo[a] = std::numeric_limits<double>::infinity();
    node.hi[a] = -std::numeric_limits<double>::infinity();
  }
  node.rmax = 0.0;
  for (std::int32_t k = begin; k < end; ++k) {
    const std::int32_t i = order[k];
    for (int a = 0; a < 3; ++a) {
      node.lo[a] = std::min(node.lo[a], C(i, a));
      node.hi[a] = std::max(node.hi[a], C(i, a));
    }
    node.rmax = std::max(node.rmax, R[i]);
  }
  // Affine radius bound: beta by least squares (r ~ beta . (c - mean)), then
  // alpha = max(r - beta . c) makes r <= alpha + beta . c exact.
  {
    const double m = static_cast<double>(end - begin);
    Vec3 mc = Vec3::Zero();
    double mr = 0.0;
    for (std::int32_t k = begin; k < end; ++k) {
      mc += C.row(order[k]).transpose();
      mr += R[order[k]];
    }
    mc /= m;
    mr /= m;
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    Vec3 cr = Vec3::Zero();
    for (std::int32_t k = begin; k < end; ++k) {
      const Vec3 d = C.row(order[k]).transpose() - mc;
      cov += d * d.transpose();
      cr += d * (R[order[k]] - mr);
    }
    // Regularised: flat (2D) or tiny nodes get beta ~ 0 along missing axes.
    cov.diagonal().array() += 1e-9 * cov.trace() + 1e-300;
    Vec3 beta = cov.ldlt().solve(cr);
    if (!beta.allFinite()) beta.setZero();
    double alpha = -std::numeric_limits<double>::infinity();
    for (std::int32_t k = begin; k < end; ++k)
      alpha = std::max(alpha, R[order[k]] - beta.dot(C.row(order[k]).transpose()));
    for (int a = 0; a < 3; ++a) node.beta[a] = beta[a];
    node.k = alpha;
    for (int a = 0; a < 3; ++a) {
      node.mid[a] = 0.5 * (node.lo[a] + node.hi[a]);
      node.half[a] = 0.5 * (node.hi[a] - node.lo[a]) * (1.0 + 1e-12) + 1e-300;
      node.k += beta[a] * node.mid[a];
    }
  }
  node.begin = begin;
  const std::int32_t n = end - begin;
  if (n <= kLeafSize) {
    node.count = n;
    node.right = -1;
    return;
  }
  node.count = 0;
  int axis = 0;
  for (int a = 1; a < 3; ++a)
    if (node.hi[a] - node.lo[a] > node.hi[axis] - node.lo[axis]) axis = a;
  const std::int32_t mid = begin + n / 2;
  // Ties broken by index: the halves are the same sets on every platform.
  std::nth_element(order.begin() + begin, order.begin() + mid, order.begin() + end,
                   [&](std::int32_t p, std::int32_t q) {
                     return C(p, axis) < C(q, axis) || (C(p, axis) == C(q, axis) && p < q);
                   });
  const std::int32_t left = ni + 1;
  const std::int32_t right = left + NodeCount(mid - begin);
  node.right = right;
  if (n > kParallelBuild) {
    tbb::parallel_invoke([&] { Build(order, begin, mid, left, C, R); },
                         [&] { Build(order, mid, end, right, C, R); });
  } else {
    Build(order, begin, mid, left, C, R);
    Build(order, mid, end, right, C, R);
  }
}

double SphereTree::MaxRadius() const { return nodes_.empty() ? 0.0 : nodes_[0].rmax; }

std::size_t SphereTree::MemoryBytes() const {
  return nodes_.capacity() * sizeof(Node) + balls_.capacity() * sizeof(Ball) +
         ids_.capacity() * sizeof(int);
}

namespace {

// Squared distance from x to the box [lo, hi].
template <class NodeT>
inline double BoxDist2(const NodeT& n, const Vec3& x) {
  double d2 = 0.0;
  for (int a = 0; a < 3; ++a) {
    const double v = x[a];
    if (v < n.lo[a]) d2 += Sq(n.lo[a] - v);
    else if (v > n.hi[a]) d2 += Sq(v - n.hi[a]);
  }
  return d2;
}

inline double BallDist2(const SphereTree::Ball& b, const Vec3& x) {
  return Sq(x[0] - b.x) + Sq(x[1] - b.y) + Sq(x[2] - b.z);
}

}  // namespace

double SphereTree::LowerBound(const Node& n, const Vec3& x, double scale, double cut) const {
  const double box = std::sqrt(BoxDist2(n, x)) - scale * n.rmax;
  if (box >= cut) return box;  // the larger bound is >= cut as well
  // With r <= alpha + beta . c over the node and |v| >= u . v for v = c - x
  // and the unit u = w / |w| toward the box centre m (w = m - x):
  //   |x - c| - s r >= (u - s beta) . v - s (beta . x + alpha),
  // whose minimum over the box (half sides h) is
  //   (u - s beta) . w - sum_a |u_a - s beta_a| h_a - s (beta . x + alpha)
  //   = |w| - s (beta . m + alpha) - sum_a |w_a - s |w| beta_a| h_a / |w|.
  const double w[3] = {n.mid[0] - x[0], n.mid[1] - x[1], n.mid[2] - x[2]};
  const double wn = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
  if (!(wn > 0.0)) return box;
  // spread / wn as spread times 1 / wn: the division no longer waits for
  // the spread (it was the bound's longest chain); the product is within a
  // few ulps of the quotient, far inside the margin below.
  const double inv = 1.0 / wn;
  const double sw = scale * wn;
  const double spread = std::abs(w[0] - sw * n.beta[0]) * n.half[0] + std::abs(w[1] - sw * n.beta[1]) * n.half[1] +
                        std::abs(w[2] - sw * n.beta[2]) * n.half[2];
  const double sk = scale * n.k;
  const double q = spread * inv;
  const double lin = wn - sk - q;
  // Rounding: a relative 1e-12 of the terms keeps the bound below the exact one.
  return std::max(box, lin - 1e-12 * (wn + std::abs(sk) + q));
}

double SphereTree::OffsetBound(const Node& n, const Vec3& x, double offset) const {
  // No ball below n has r + offset > 0: none can contain x.
  return n.rmax + offset > 0.0 ? LowerBound(n, x, 1.0, offset) : offset;
}

void SphereTree::CollectLocal(const Vec3& lo, const Vec3& hi, double offset, LocalSet* set) const {
  set->lo = lo;
  set->hi = hi;
  set->offset = offset;
  set->balls.clear();
  if (nodes_.empty()) return;
  // For x in the box: |x - c| - r >= dist(c, box) - r, and >= (bound at the
  // box centre) - half diagonal.
  const Vec3 mid = 0.5 * (lo + hi);
  const double hd = 0.5 * (hi - lo).norm();
  std::int32_t stack[kStack];
  int sp = 0;
  stack[sp++] = 0;
  while (sp > 0) {
    const Node& n = nodes_[stack[--sp]];
    double gap2 = 0.0;
    for (int a = 0; a < 3; ++a) {
      if (n.hi[a] < lo[a]) gap2 += Sq(lo[a] - n.hi[a]);
      else if (n.lo[a] > hi[a]) gap2 += Sq(n.lo[a] - hi[a]);
    }
    if (std::sqrt(gap2) - n.rmax >= offset) continue;
    if (LowerBound(n, mid, 1.0) - hd >= offset) continue;
    if (n.count > 0) {
      for (std::int32_t k = n.begin; k < n.begin + n.count; ++k) {
        const Ball& b = balls_[k];
        double d2 = 0.0;
        const double c[3] = {b.x, b.y, b.z};
        for (int a = 0; a < 3; ++a) {
          if (c[a] < lo[a]) d2 += Sq(lo[a] - c[a]);
          else if (c[a] > hi[a]) d2 += Sq(c[a] - hi[a]);
        }
        if (std::sqrt(d2) - b.r < offset) set->balls.push_back(k);
      }
      continue;
    }
    stack[sp++] = n.right;
    stack[sp++] = static_cast<std::int32_t>(&n - nodes_.data()) + 1;
  }
}

int SphereTree::FindContaining(const Vec3& x, double offset, int ignore_id, const LocalSet* local) const {
  if (local && local->Serves(x, offset)) {
    for (int k : local->balls) {
      if (Contains(k, x, offset, ignore_id)) return k;
    }
    return -1;
  }
  if (nodes_.empty()) return -1;
  // Each child's bound is computed once, by its parent: children it rules
  // out are not pushed, and the one with the lower bound (the likelier to
  // hold a containing ball) is popped first.
  auto bound = [&](std::int32_t i) { return OffsetBound(nodes_[i], x, offset); };
  std::int32_t stack[kStack];
  int sp = 0;
  if (bound(0) < offset) stack[sp++] = 0;
  while (sp > 0) {
    const Node& n = nodes_[stack[--sp]];
    if (n.count > 0) {
      for (std::int32_t k = n.begin; k < n.begin + n.count; ++k) {
        if (Contains(k, x, offset, ignore_id)) return k;
      }
      continue;
    }
    const std::int32_t l = static_cast<std::int32_t>(&n - nodes_.data()) + 1, r = n.right;
    const double bl = bound(l), br = bound(r);
    if (bl < offset && br < offset) {
      stack[sp++] = bl <= br ? r : l;
      stack[sp++] = bl <= br ? l : r;
    } else if (bl < offset) {
      stack[sp++] = l;
    } else if (br < offset) {
      stack[sp++] = r;
    }
  }
  return -1;
}

void SphereTree::CollectContaining(const Vec3& x, double offset, int ignore_id, std::vector<int>* ids) const {
  if (nodes_.empty()) return;
  std::int32_t stack[kStack];
  int sp = 0;
  stack[sp++] = 0;
  while (sp > 0) {
    const Node& n = nodes_[stack[--sp]];
    if (OffsetBound(n, x, offset) >= offset) continue;
    if (n.count > 0) {
      for (std::int32_t k = n.begin; k < n.begin + n.count; ++k)
        if (Contains(k, x, offset, ignore_id)) ids->push_back(ids_[k]);
      continue;
    }
    stack[sp++] = n.right;
    stack[sp++] = static_cast<std::int32_t>(&n - nodes_.data()) + 1;
  }
}

void SphereTree::DeepestContaining(const Vec3& x, double offset, int k, int ignore_id, std::vector<int>* out,
                                   const LocalSet* local) const {
  out->clear();
  if (nodes_.empty() || k <= 0) return;
  if (local && local->Serves(x, offset)) {
    // Same keys, same order (key, id) as the tree traversal below.
    thread_local std::vector<std::pair<std::pair<double, int>, int>> keys;
    keys.clear();
    for (int j : local->balls) {
      if (ids_[j] == ignore_id) continue;
      const double key = std::sqrt(BallDist2(balls_[j], x)) - balls_[j].r;
      if (key < offset) keys.push_back({{key, ids_[j]}, j});
    }
    const std::size_t kk = std::min<std::size_t>(k, keys.size());
    std::partial_sort(keys.begin(), keys.begin() + kk, keys.end());
    for (std::size_t t = 0; t < kk; ++t) out->push_back(keys[t].second);
    return;
  }
  // Max-heap of the best k (key, id, tree index); worst on top.
  struct Item {
    double key;
    int id;
    int index;
    bool operator<(const Item& o) const { return key < o.key || (key == o.key && id < o.id); }
  };
  std::priority_queue<Item> heap;
  auto threshold = [&]() {
    return static_cast<int>(heap.size()) < k ? offset : heap.top().key;
  };
  std::pair<std::int32_t, double> stack[kStack];
  int sp = 0;
  stack[sp++] = {0, LowerBound(nodes_[0], x, 1.0)};
  while (sp > 0) {
    const auto [ni, bound] = stack[--sp];
    // Keys equal to a full heap's worst can still win on id, so prune on '>'.
    if (bound > threshold() || (static_cast<int>(heap.size()) < k && bound >= offset)) continue;
    const Node& n = nodes_[ni];
    if (n.count > 0) {
      for (std::int32_t j = n.begin; j < n.begin + n.count; ++j) {
        if (ids_[j] == ignore_id) continue;
        const double key = std::sqrt(BallDist2(balls_[j], x)) - balls_[j].r;
        if (!(key < offset)) continue;
        const Item it{key, ids_[j], j};
        if (static_cast<int>(heap.size()) < k) {
          heap.push(it);
        } else if (it < heap.top()) {
          heap.pop();
          heap.push(it);
        }
      }
      continue;
    }
    // A child whose box bound alone reaches the threshold is pruned when
    // popped (the threshold only falls), so its affine bound is not needed.
    const std::int32_t l = ni + 1, r = n.right;
    const double cut = threshold();
    const double bl = LowerBound(nodes_[l], x, 1.0, cut);
    const double br = LowerBound(nodes_[r], x, 1.0, cut);
    if (bl <= br) {
      stack[sp++] = {r, br};
      stack[sp++] = {l, bl};
    } else {
      stack[sp++] = {l, bl};
      stack[sp++] = {r, br};
    }
  }
  std::vector<Item> items;
  items.reserve(heap.size());
  while (!heap.empty()) {
    items.push_back(heap.top());
    heap.pop();
  }
  std::sort(items.begin(), items.end());
  for (const Item& it : items) out->push_back(it.index);
}

bool SphereTree::AnyCovers(const Vec3& x, double scale2) const {
  if (nodes_.empty()) return false;
  std::int32_t stack[kStack];
  int sp = 0;
  stack[sp++] = 0;
  while (sp > 0) {
    const Node& n = nodes_[stack[--sp]];
    if (BoxDist2(n, x) > scale2 * n.rmax * n.rmax) continue;
    if (n.count > 0) {
      for (std::int32_t k = n.begin; k < n.begin + n.count; ++k)
        if (BallDist2(balls_[k], x) <= scale2 * balls_[k].r * balls_[k].r) return true;
      continue;
    }
    const std::int32_t l = static_cast<std::int32_t>(&n - nodes_.data()) + 1, r = n.right;
    if (BoxDist2(nodes_[l], x) <= BoxDist2(nodes_[r], x)) {
      stack[sp++] = r;
      stack[sp++] = l;
    } else {
      stack[sp++] = l;
      stack[sp++] = r;
    }
  }
  return false;
}

double SphereTree::MinDistance(const Vec3& x, const std::vector<int>& balls, double stop) const {
  double best = std::numeric_limits<double>::infinity();
  for (int k : balls) {
    best = std::min(best, std::sqrt(BallDist2(balls_[k], x)) - 1.0 * balls_[k].r);
    if (best <= stop) break;
  }
  return best;
}

double SphereTree::DistanceToUnion(const Vec3& x, double scale) const {
  double best = std::numeric_limits<double>::infinity();
  if (nodes_.empty()) return best;
  std::pair<std::int32_t, double> stack[kStack];
  int sp = 0;
  stack[sp++] = {0, -std::numeric_limits<double>::infinity()};
  while (sp > 0) {
    const auto [ni, bound] = stack[--sp];
    if (bound >= best) continue;
    const Node& n = nodes_[ni];
    if (n.count > 0) {
      for (std::int32_t k = n.begin; k < n.begin + n.count; ++k)
        best = std::min(best, std::sqrt(BallDist2(balls_[k], x)) - scale * balls_[k].r);
      continue;
    }
    const std::int32_t l = ni + 1, r = n.right;
    const double bl = LowerBound(nodes_[l], x, scale);
    const double br = LowerBound(nodes_[r], x, scale);
    if (bl <= br) {
      stack[sp++] = {r, br};
      stack[sp++] = {l, bl};
    } else {
      stack[sp++] = {l, bl};
      stack[sp++] = {r, br};
    }
  }
  return best;
}

namespace {

// Squared gap between the intervals [alo, ahi] and [blo, bhi], summed over axes.
inline double BoxBoxDist2(const double* alo, const double* ahi, const Vec3& blo, const Vec3& bhi) {
  double d2 = 0.0;
  for (int a = 0; a < 3; ++a) {
    if (ahi[a] < blo[a]) d2 += Sq(blo[a] - ahi[a]);
    else if (alo[a] > bhi[a]) d2 += Sq(alo[a] - bhi[a]);
  }
  return d2;
}

// Lower bound, over centres c in [nlo, nhi], of the squared distance from c to
// the farthest corner of the box with centre `mid` and half sizes `half`.
inline double FarCornerLowerBound2(const double* nlo, const double* nhi, const Vec3& mid,
                                   const Vec3& half) {
  double d2 = 0.0;
  for (int a = 0; a < 3; ++a) {
    double g = 0.0;
    if (mid[a] < nlo[a]) g = nlo[a] - mid[a];
    else if (mid[a] > nhi[a]) g = mid[a] - nhi[a];
    d2 += Sq(g + half[a]);
  }
  return d2;
}

}  // namespace

bool SphereTree::AnyIntersectsBox(const Vec3& lo, const Vec3& hi, double scale2) const {
  if (nodes_.empty()) return false;
  // For x in the box: |x - c| - s r >= (bound at the box centre) - half diagonal.
  const Vec3 mid = 0.5 * (lo + hi);
  const double hd = 0.5 * (hi - lo).norm(), s = std::sqrt(scale2);
  std::int32_t stack[kStack];
  int sp = 0;
  stack[sp++] = 0;
  while (sp > 0) {
    const Node& n = nodes_[stack[--sp]];
    if (BoxBoxDist2(n.lo, n.hi, lo, hi) > scale2 * n.rmax * n.rmax) continue;
    if (LowerBound(n, mid, s) > hd * (1.0 + 1e-12)) continue;
    if (n.count > 0) {
      for (std::int32_t k = n.begin; k < n.begin + n.count; ++k) {
        const Ball& b = balls_[k];
        const double c[3] = {b.x, b.y, b.z};
        if (BoxBoxDist2(c, c, lo, hi) <= scale2 * b.r * b.r) return true;
      }
      continue;
    }
    stack[sp++] = n.right;
    stack[sp++] = static_cast<std::int32_t>(&n - nodes_.data()) + 1;
  }
  return false;
}

bool SphereTree::AnyCoversBox(const Vec3& lo, const Vec3& hi, double scale2) const {
  if (nodes_.empty()) return false;
  const Vec3 mid = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
  const double hd = half.norm(), s = std::sqrt(scale2);
  std::int32_t stack[kStack];
  int sp = 0;
  stack[sp++] = 0;
  while (sp > 0) {
    const Node& n = nodes_[stack[--sp]];
    if (FarCornerLowerBound2(n.lo, n.hi, mid, half) > scale2 * n.rmax * n.rmax) continue;
    // Covering needs |mid - c|^2 + hd^2 <= (s r)^2 (opposite corners), so
    // |mid - c| - s r <= -hd^2 / (2 s r) <= -hd^2 / (2 s rmax).
    if (LowerBound(n, mid, s) > -(hd * hd) / (2.0 * s * n.rmax) * (1.0 - 1e-9)) continue;
    if (n.count > 0) {
      for (std::int32_t k = n.begin; k < n.begin + n.count; ++k) {
        const Ball& b = balls_[k];
        const double c[3] = {b.x, b.y, b.z};
        if (FarCornerLowerBound2(c, c, mid, half) <= scale2 * b.r * b.r) return true;
      }
      continue;
    }
    stack[sp++] = n.right;
    stack[sp++] = static_cast<std::int32_t>(&n - nodes_.data()) + 1;
  }
  return false;
}

void SphereTree::CollectIntersectingBox(const Vec3& lo, const Vec3& hi, double scale2,
                                        std::vector<int>* out) const {
  if (nodes_.empty()) return;
  const Vec3 mid = 0.5 * (lo + hi);
  const double hd = 0.5 * (hi - lo).norm(), s = std::sqrt(scale2);
  std::int32_t stack[kStack];
  int sp = 0;
  stack[sp++] = 0;
  while (sp > 0) {
    const Node& n = nodes_[stack[--sp]];
    if (BoxBoxDist2(n.lo, n.hi, lo, hi) > scale2 * n.rmax * n.rmax) continue;
    if (LowerBound(n, mid, s) > hd * (1.0 + 1e-12)) continue;
    if (n.count > 0) {
      for (std::int32_t k = n.begin; k < n.begin + n.count; ++k) {
        const Ball& b = balls_[k];
        const double c[3] = {b.x, b.y, b.z};
        if (BoxBoxDist2(c, c, lo, hi) <= scale2 * b.r * b.r) out->push_back(k);
      }
      continue;
    }
    stack[sp++] = n.right;
    stack[sp++] = static_cast<std::int32_t>(&n - nodes_.data()) + 1;
  }
}

}  // namespace arcs
