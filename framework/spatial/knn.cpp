// kd-tree nearest neighbours over nanoflann.
//
// The points are stored in Morton (Z-curve) order so that a kd-tree leaf reads
// contiguous memory; indices are mapped back to the caller's order. Batch
// queries are also processed in Morton order (cache reuse) and warm started
// with the distance to the previous query's nearest point as search radius,
// which does not change the answer: nearest = lexicographic minimum of
// (squared distance, original index). nanoflann 1.4 API (findNeighbors with a
// custom result set).
#include "framework/spatial/knn.h"

#include "framework/util/parallel.h"

#include <nanoflann.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <vector>

namespace arcs {
namespace {

// Points in sorted order, interleaved xyz.
struct Cloud {
  std::vector<double> xyz;
  std::size_t kdtree_get_point_count() const { return xyz.size() / 3; }
  double kdtree_get_pt(std::size_t i, std::size_t d) const { return xyz[3 * i + d]; }
  template <class Bbox>
  bool kdtree_get_bbox(Bbox&) const {
    return false;
  }
};

using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Cloud, double, std::uint32_t>,
                                                 Cloud, 3, std::uint32_t>;

// 1-NN result set with an initial radius and lowest-original-index ties.
class NearestResult {
 public:
  using DistanceType = double;
  using IndexType = std::uint32_t;
  NearestResult(double max_sq, const int* original) : best_(max_sq), original_(original) {}
  std::size_t size() const { return idx_ == kNone ? 0 : 1; }
  bool full() const { return true; }
  bool addPoint(double d, std::uint32_t i) {
    if (d < best_ || (d == best_ && (idx_ == kNone || original_[i] < original_[idx_]))) {
      best_ = d;
      idx_ = i;
    }
    return true;
  }
  // Slightly above the best so that exact ties (also at distance 0) still
  // reach addPoint, which decides exactly (nanoflann prunes with rounded
  // incremental box distances and tests `dist < worstDist()` at leaves).
  double worstDist() const { return best_ * (1.0 + 1e-12) + 0x1p-1074; }
  double best() const { return best_; }
  std::uint32_t index() const { return idx_; }
  static constexpr std::uint32_t kNone = 0xffffffffu;

 private:
  double best_;
  std::uint32_t idx_ = kNone;
  const int* original_;
};

}  // namespace

// Indices in Morton (Z-curve) order of 10 bits per axis over the bounding box
// (1024^3 cells; order inside a cell is by index). Keys (code << 32 | index)
// are sorted by an LSD radix sort of the 30 code bits, 3 passes of 10 bits.
std::vector<int> MortonOrder(const MatrixX3d& P) {
  const std::int64_t n = P.rows();
  std::vector<int> order(n);
  if (n == 0) return order;
  const Vec3 lo = P.colwise().minCoeff().transpose(), hi = P.colwise().maxCoeff().transpose();
  const double ext = std::max((hi - lo).maxCoeff(), 1e-300);
  const double scale = 1023.0 / ext;
  auto spread = [](std::uint64_t x) {  // 10 bits -> every third bit
    x &= 0x3ff;
    x = (x | x << 16) & 0x30000ffull;
    x = (x | x << 8) & 0x300f00full;
    x = (x | x << 4) & 0x30c30c3ull;
    x = (x | x << 2) & 0x9249249ull;
    return x;
  };
  std::vector<std::uint64_t> a(n), b(n);
  ParallelFor(
      n,
      [&](std::int64_t begin, std::int64_t end) {
        for (std::int64_t i = begin; i < end; ++i) {
          std::uint64_t c[3];
          for (int k = 0; k < 3; ++k) {
            double v = (P(i, k) - lo[k]) * scale;
            v = v >= 0.0 ? std::min(v, 1023.0) : 0.0;  // also maps NaN to 0
            c[k] = static_cast<std::uint64_t>(v);
          }
          const std::uint64_t code = spread(c[0]) | spread(c[1]) << 1 | spread(c[2]) << 2;
          a[i] = code << 32 | static_cast<std::uint64_t>(i);
        }
      },
      1 << 16);
  for (int shift = 32; shift < 62; shift += 10) {
    std::int64_t count[1025] = {};
    for (std::int64_t i = 0; i < n; ++i) ++count[((a[i] >> shift) & 0x3ff) + 1];
    for (int d = 0; d < 1024; ++d) count[d + 1] += count[d];
    for (std::int64_t i = 0; i < n; ++i) b[count[(a[i] >> shift) & 0x3ff]++] = a[i];
    a.swap(b);
  }
  for (std::int64_t i = 0; i < n; ++i) order[i] = static_cast<int>(a[i] & 0xffffffffu);
  return order;
}

struct KdTree3::Impl {
  Cloud cloud;
  std::vector<int> original;  // sorted position -> caller's index
  std::unique_ptr<Tree> tree;

  // Nearest with a squared radius bound; returns the sorted index or kNone.
  std::uint32_t Nearest(const double* q, double max_sq, double* d2) const {
    NearestResult res(max_sq, original.data());
    tree->findNeighbors(res, q, nanoflann::SearchParams());
    *d2 = res.best();
    return res.index();
  }
};

KdTree3::KdTree3(const MatrixX3d& P) : impl_(std::make_unique<Impl>()) {
  impl_->original = MortonOrder(P);
  const std::size_t n = P.rows();
  impl_->cloud.xyz.resize(3 * n);
  for (std::size_t i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) impl_->cloud.xyz[3 * i + k] = P(impl_->original[i], k);
  impl_->tree = std::make_unique<Tree>(3, impl_->cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
}

KdTree3::~KdTree3() = default;
KdTree3::KdTree3(KdTree3&&) noexcept = default;
KdTree3& KdTree3::operator=(KdTree3&&) noexcept = default;

int KdTree3::Size() const { return static_cast<int>(impl_->original.size()); }

int KdTree3::Nearest(const Vec3& q, double* sq_dist) const {
  if (Size() == 0) {
    if (sq_dist) *sq_dist = std::numeric_limits<double>::infinity();
    return -1;
  }
  const double p[3] = {q.x(), q.y(), q.z()};
  double d2;
  const std::uint32_t i = impl_->Nearest(p, std::numeric_limits<double>::infinity(), &d2);
  if (sq_dist) *sq_dist = d2;
  return i == NearestResult::kNone ? -1 : impl_->original[i];
}

void KdTree3::NearestBatch(const MatrixX3d& Q, Eigen::VectorXi* index, VectorXd* sq_dist) const {
  const std::int64_t n = Q.rows();
  if (index) index->resize(n);
  if (sq_dist) sq_dist->resize(n);
  if (n == 0) return;
  if (Size() == 0) {
    if (index) index->setConstant(-1);
    if (sq_dist) sq_dist->setConstant(std::numeric_limits<double>::infinity());
    return;
  }
  const std::vector<int> order = MortonOrder(Q);
  ParallelFor(
      n,
      [&](std::int64_t begin, std::int64_t end) {
        // Warm start: the previous query's nearest point bounds this query's
        // distance from above (queries run in Morton order, so it is usually
        // the answer or close to it). The answer does not depend on it.
        std::uint32_t prev = NearestResult::kNone;
        const double* xyz = impl_->cloud.xyz.data();
        for (std::int64_t s = begin; s < end; ++s) {
          const std::int64_t i = order[s];
          const double q[3] = {Q(i, 0), Q(i, 1), Q(i, 2)};
          double d2 = std::numeric_limits<double>::infinity();
          std::uint32_t j = NearestResult::kNone;
          if (prev != NearestResult::kNone) {
            const double dx = q[0] - xyz[3 * prev], dy = q[1] - xyz[3 * prev + 1],
                         dz = q[2] - xyz[3 * prev + 2];
            const double ub = dx * dx + dy * dy + dz * dz;
            j = impl_->Nearest(q, ub * (1.0 + 1e-12) + 1e-300, &d2);
          }
          if (j == NearestResult::kNone)
            j = impl_->Nearest(q, std::numeric_limits<double>::infinity(), &d2);
          prev = j;
          if (index) (*index)[i] = impl_->original[j];
          if (sq_dist) (*sq_dist)[i] = d2;
        }
      },
      1024);
}

std::vector<int> KdTree3::Knn(const Vec3& q, int k, std::vector<double>* sq_dists) const {
  std::vector<int> out;
  if (sq_dists) sq_dists->clear();
  const int kk = std::min(k, Size());
  if (kk <= 0) return out;
  std::vector<std::uint32_t> idx(kk);
  std::vector<double> d2(kk);
  nanoflann::KNNResultSet<double, std::uint32_t> res(kk);
  res.init(idx.data(), d2.data());
  const double p[3] = {q.x(), q.y(), q.z()};
  impl_->tree->findNeighbors(res, p, nanoflann::SearchParams());
  const int found = static_cast<int>(res.size());
  // Deterministic order: by distance, then by original index.
  std::vector<std::pair<double, int>> pairs(found);
  for (int i = 0; i < found; ++i) pairs[i] = {d2[i], impl_->original[idx[i]]};
  std::sort(pairs.begin(), pairs.end());
  out.resize(found);
  if (sq_dists) sq_dists->resize(found);
  for (int i = 0; i < found; ++i) {
    out[i] = pairs[i].second;
    if (sq_dists) (*sq_dists)[i] = pairs[i].first;
  }
  return out;
}

void KdTree3::KnnBatch(const MatrixX3d& Q, int k,
                       Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>* out) const {
  const std::int64_t n = Q.rows();
  out->resize(n, std::max(k, 0));
  if (k <= 0) return;
  out->setConstant(-1);
  ParallelFor(
      n,
      [&](std::int64_t begin, std::int64_t end) {
        for (std::int64_t i = begin; i < end; ++i) {
          const auto nn = Knn(Vec3(Q(i, 0), Q(i, 1), Q(i, 2)), k);
          for (std::size_t j = 0; j < nn.size(); ++j) (*out)(i, j) = nn[j];
        }
      },
      256);
}

}  // namespace arcs
