// A bounding-volume hierarchy over balls, for the queries RFTA is built on
// (paper §4.1: "is x contained in any sphere?", "which spheres contain x?").
//
// Nodes bound their balls by the box of the centres plus the largest radius
// (dist(query, centre box) - largest radius <= |x - c| - r) and by an affine
// radius bound r <= alpha + beta . c (see Node); a query skips a node when the
// larger of the two bounds rules it out. Queries that take a radius `scale` test the
// balls (c, scale * r) (scale > 0), and `offset` tests (c, r + offset).
//
// All queries are read-only and thread-safe; results never depend on the
// traversal order (sets, or k-best with ties broken by id).
#pragma once

#include "framework/types.h"

#include <cstdint>
#include <limits>
#include <vector>

namespace arcs {

class SphereTree {
 public:
  struct Ball {
    double x, y, z, r;
  };

  SphereTree() = default;
  // Indexes the balls (centres[i], radii[i]) with caller ids ids[i] (ids need
  // not be unique, but `ignore_id` skips every ball with that id).
  // `members` (optional) selects a subset of the rows.
  SphereTree(const MatrixX3d& centers, const VectorXd& radii, const std::vector<int>& ids,
             const std::vector<int>* members = nullptr);

  int Size() const { return static_cast<int>(balls_.size()); }
  bool Empty() const { return balls_.empty(); }
  // Ball k in tree order (0 <= k < Size()) and its id.
  const Ball& ball(int k) const { return balls_[k]; }
  int id(int k) const { return ids_[k]; }
  double MaxRadius() const;

  // The balls that can come within `offset` of some point of a box: for any
  // x in [lo, hi], every ball with |x - c| - r < offset is in `balls`. Point
  // queries inside the box scan this short list instead of the tree, with
  // identical answers; many nearby queries share one list.
  struct LocalSet {
    Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();
    double offset = -std::numeric_limits<double>::infinity();
    std::vector<int> balls;  // tree indices
    // Whether queries at x with this offset may use the list.
    bool Serves(const Vec3& x, double query_offset) const {
      return query_offset <= offset && (x.array() >= lo.array()).all() && (x.array() <= hi.array()).all();
    }
  };
  // Fills *set for the box [lo, hi] and offset.
  void CollectLocal(const Vec3& lo, const Vec3& hi, double offset, LocalSet* set) const;

  // Containment with an additive radius offset: is there a ball other than
  // `ignore_id` with |x - c| < r + offset? (offset = -tol: "contains x by more
  // than tol", the make-feasible test.) `local` (optional) is used if it
  // serves x.
  bool AnyContains(const Vec3& x, double offset, int ignore_id, const LocalSet* local = nullptr) const {
    return FindContaining(x, offset, ignore_id, local) >= 0;
  }
  // The same test, answering with the tree index of a ball that contains x
  // (the first one met), or -1.
  int FindContaining(const Vec3& x, double offset, int ignore_id, const LocalSet* local = nullptr) const;
  // Every ball that FindContaining could name: the ids of all balls other
  // than `ignore_id` with |x - c| < r + offset, appended to *ids in tree
  // order. Whether a subset of the balls contains x is then a lookup (the
  // fine-tuner's batches are subsets of all spheres).
  void CollectContaining(const Vec3& x, double offset, int ignore_id, std::vector<int>* ids) const;
  // Does ball k (a tree index) other than `ignore_id` contain x, with the
  // offset? The leaf test of AnyContains, for callers that remember a ball.
  bool Contains(int k, const Vec3& x, double offset, int ignore_id) const {
    const double r = balls_[k].r + offset;
    const Ball& b = balls_[k];
    const double d2 = (x[0] - b.x) * (x[0] - b.x) + (x[1] - b.y) * (x[1] - b.y) + (x[2] - b.z) * (x[2] - b.z);
    return r > 0.0 && d2 < r * r && ids_[k] != ignore_id;
  }
  // The (at most k) balls other than `ignore_id` with |x - c| - r < offset,
  // deepest first (smallest |x - c| - r; ties by id). Appends tree indices to
  // *out (cleared first).
  void DeepestContaining(const Vec3& x, double offset, int k, int ignore_id, std::vector<int>* out,
                         const LocalSet* local = nullptr) const;

  // min over the balls `balls` (tree indices) of |x - c| - r, in their
  // order, stopping at the first term <= stop (returned). With a LocalSet's
  // list: DistanceToUnion(x, 1) wherever that is below the set's offset, x
  // lies in its box and no term reaches stop.
  double MinDistance(const Vec3& x, const std::vector<int>& balls,
                     double stop = -std::numeric_limits<double>::infinity()) const;

  // Scaled-ball coverage (the rasteriser's test): is there a ball with
  // |x - c|^2 <= scale2 * r^2?
  bool AnyCovers(const Vec3& x, double scale2) const;
  // min over balls of |x - c| - scale * r (the signed distance to the union
  // of the scaled balls where it is positive; a lower bound inside).
  // +infinity for an empty tree.
  double DistanceToUnion(const Vec3& x, double scale) const;

  // Box queries on the scaled balls (c, sqrt(scale2) r); boxes are [lo, hi].
  // Is there a ball intersecting the box?
  bool AnyIntersectsBox(const Vec3& lo, const Vec3& hi, double scale2) const;
  // Is there one ball containing the whole box?
  bool AnyCoversBox(const Vec3& lo, const Vec3& hi, double scale2) const;
  // Tree indices of all balls intersecting the box (appended to *out).
  void CollectIntersectingBox(const Vec3& lo, const Vec3& hi, double scale2,
                              std::vector<int>* out) const;

  // Memory held by the tree, in bytes.
  std::size_t MemoryBytes() const;

 private:
  struct Node {
    double lo[3], hi[3];  // box of the centres
    double rmax;          // largest radius below the node
    // Affine radius bound r <= alpha + beta . c over the node's balls (beta
    // fitted by least squares). SDF radii are nearly affine in the centre
    // over a small region (|grad| = 1), which makes this bound much tighter
    // than rmax near the surface, where thousands of balls are almost tangent.
    // Stored as beta and k = beta . mid + alpha (LowerBound's affine term
    // needs alpha only there), with the centres' box as centre and half
    // sides (widened by a relative 1e-12, so the box they span holds
    // [lo, hi] despite rounding).
    double beta[3];
    double k;
    double mid[3], half[3];
    std::int32_t begin;   // first ball (tree order)
    std::int32_t count;   // > 0: leaf with `count` balls; 0: inner node
    std::int32_t right;   // inner node: index of the right child (left = this + 1)
  };
  void Build(std::vector<std::int32_t>& order, std::int32_t begin, std::int32_t end,
             std::int32_t node_index, const MatrixX3d& centers, const VectorXd& radii);
  static std::int32_t NodeCount(std::int32_t n);

  // Lower bound of |x - c| - scale * r over the balls below node n. With a
  // `cut`: once the box bound alone reaches it, that bound is returned (a
  // caller that only asks "below cut?" gets the same answer, and the same
  // value whenever the answer is yes).
  double LowerBound(const Node& n, const Vec3& x, double scale,
                    double cut = std::numeric_limits<double>::infinity()) const;
  // The containment queries' node test (FindContaining, CollectContaining):
  // a value >= offset rules node n out for "|x - c| < r + offset"; below
  // offset it is LowerBound's exact value.
  double OffsetBound(const Node& n, const Vec3& x, double offset) const;

  std::vector<Node> nodes_;
  std::vector<Ball> balls_;
  std::vector<int> ids_;
};

}  // namespace arcs
