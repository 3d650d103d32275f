#include "framework/spatial/polyline_query.h"

#include "framework/error.h"
#include "framework/util/parallel.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

namespace arcs {

namespace {

using V2 = Eigen::Vector2d;

struct Node {
  V2 lo, hi;
  int left = -1, right = -1;  // children; -1 for a leaf
  int begin = 0, end = 0;     // leaf: range in Impl::order
};

// Closest point on segment [a, b] to q, as the parameter t in [0, 1].
inline double SegmentParam(const V2& a, const V2& b, const V2& q) {
  const V2 d = b - a;
  const double l2 = d.squaredNorm();
  if (l2 <= 0) return 0.0;
  return std::clamp((q - a).dot(d) / l2, 0.0, 1.0);
}

inline double BoxSqDist(const Node& n, const V2& q) {
  const double dx = std::max({n.lo.x() - q.x(), 0.0, q.x() - n.hi.x()});
  const double dy = std::max({n.lo.y() - q.y(), 0.0, q.y() - n.hi.y()});
  return dx * dx + dy * dy;
}

constexpr int kLeafSize = 4;

}  // namespace

struct SegmentBvh::Impl {
  Polyline curve;
  std::vector<V2> a, b;  // segment endpoints per edge
  std::vector<int> order;
  std::vector<Node> nodes;

  int Build(int begin, int end) {
    Node n;
    n.lo = V2::Constant(std::numeric_limits<double>::infinity());
    n.hi = -n.lo;
    for (int k = begin; k < end; ++k) {
      const int e = order[k];
      n.lo = n.lo.cwiseMin(a[e]).cwiseMin(b[e]);
      n.hi = n.hi.cwiseMax(a[e]).cwiseMax(b[e]);
    }
    const int id = static_cast<int>(nodes.size());
    nodes.push_back(n);
    if (end - begin <= kLeafSize) {
      nodes[id].begin = begin;
      nodes[id].end = end;
      return id;
    }
    const int axis = (n.hi - n.lo).x() >= (n.hi - n.lo).y() ? 0 : 1;
    const int mid = (begin + end) / 2;
    std::nth_element(order.begin() + begin, order.begin() + mid, order.begin() + end, [&](int x, int y) {
      const double cx = a[x][axis] + b[x][axis], cy = a[y][axis] + b[y][axis];
      return cx < cy || (cx == cy && x < y);
    });
    const int l = Build(begin, mid);
    const int r = Build(mid, end);
    nodes[id].left = l;
    nodes[id].right = r;
    return id;
  }

  SegmentBvh::Hit Closest(const V2& q) const {
    SegmentBvh::Hit best;
    if (nodes.empty()) return best;
    double best_d = std::numeric_limits<double>::infinity();
    int best_e = -1;
    double best_t = 0;
    int stack[128];
    int sp = 0;
    stack[sp++] = 0;
    while (sp > 0) {
      const Node& n = nodes[stack[--sp]];
      if (BoxSqDist(n, q) > best_d) continue;
      if (n.left < 0) {
        for (int k = n.begin; k < n.end; ++k) {
          const int e = order[k];
          const double t = SegmentParam(a[e], b[e], q);
          const double d = ((1 - t) * a[e] + t * b[e] - q).squaredNorm();
          if (d < best_d || (d == best_d && e < best_e)) {
            best_d = d;
            best_e = e;
            best_t = t;
          }
        }
        continue;
      }
      const double dl = BoxSqDist(nodes[n.left], q), dr = BoxSqDist(nodes[n.right], q);
      // Push the farther child first so the nearer is visited first.
      if (dl <= dr) {
        stack[sp++] = n.right;
        stack[sp++] = n.left;
      } else {
        stack[sp++] = n.left;
        stack[sp++] = n.right;
      }
    }
    best.sq_dist = best_d;
    best.edge = best_e;
    const V2 p = (1 - best_t) * a[best_e] + best_t * b[best_e];
    best.point = Vec3(p.x(), p.y(), 0.0);
    return best;
  }
};

SegmentBvh::SegmentBvh(const Polyline& curve) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.curve = curve;
  const int ne = curve.NumEdges();
  m.a.resize(ne);
  m.b.resize(ne);
  for (int e = 0; e < ne; ++e) {
    for (int k = 0; k < 2; ++k)
      if (curve.E(e, k) < 0 || curve.E(e, k) >= curve.NumVertices())
        throw InputError("", 0, "SegmentBvh: edge " + std::to_string(e) + " refers to vertex " +
                                    std::to_string(curve.E(e, k)) + " of " + std::to_string(curve.NumVertices()));
    m.a[e] = curve.V.row(curve.E(e, 0)).head<2>().transpose();
    m.b[e] = curve.V.row(curve.E(e, 1)).head<2>().transpose();
  }
  m.order.resize(ne);
  std::iota(m.order.begin(), m.order.end(), 0);
  if (ne > 0) {
    m.nodes.reserve(2 * (ne / kLeafSize + 1));
    m.Build(0, ne);
  }
}

SegmentBvh::~SegmentBvh() = default;
SegmentBvh::SegmentBvh(SegmentBvh&&) noexcept = default;
SegmentBvh& SegmentBvh::operator=(SegmentBvh&&) noexcept = default;

SegmentBvh::Hit SegmentBvh::Closest(const Vec3& q) const { return impl_->Closest(V2(q.x(), q.y())); }

void SegmentBvh::ClosestPoints(const MatrixX3d& Q, VectorXd* sq_dist, MatrixX3d* points,
                               Eigen::VectorXi* edges) const {
  const Eigen::Index n = Q.rows();
  if (sq_dist) sq_dist->resize(n);
  if (points) points->resize(n, 3);
  if (edges) edges->resize(n);
  ParallelFor(n, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t i = begin; i < end; ++i) {
      const Hit h = impl_->Closest(V2(Q(i, 0), Q(i, 1)));
      if (sq_dist) (*sq_dist)[i] = h.sq_dist;
      if (points) points->row(i) = h.point.transpose();
      if (edges) (*edges)[i] = h.edge;
    }
  }, 256);
}

const Polyline& SegmentBvh::curve() const { return impl_->curve; }

double WindingNumber2D(const Polyline& curve, const Vec3& q) {
  double sum = 0;
  for (int e = 0; e < curve.NumEdges(); ++e) {
    const double ax = curve.V(curve.E(e, 0), 0) - q.x(), ay = curve.V(curve.E(e, 0), 1) - q.y();
    const double bx = curve.V(curve.E(e, 1), 0) - q.x(), by = curve.V(curve.E(e, 1), 1) - q.y();
    sum += std::atan2(ax * by - ay * bx, ax * bx + ay * by);
  }
  return sum / (2 * std::numbers::pi);
}

VectorXd WindingNumbers2D(const Polyline& curve, const MatrixX3d& Q) {
  for (int e = 0; e < curve.NumEdges(); ++e)
    for (int k = 0; k < 2; ++k)
      if (curve.E(e, k) < 0 || curve.E(e, k) >= curve.NumVertices())
        throw InputError("", 0, "WindingNumbers2D: edge " + std::to_string(e) + " refers to vertex " +
                                    std::to_string(curve.E(e, k)) + " of " + std::to_string(curve.NumVertices()));
  VectorXd w(Q.rows());
  ParallelFor(Q.rows(), [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t i = begin; i < end; ++i) w[i] = WindingNumber2D(curve, Q.row(i).transpose());
  }, 64);
  return w;
}

}  // namespace arcs
