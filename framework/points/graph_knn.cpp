// Step 1 of the graph-Voronoi reconstruction: the symmetric κNN graph.
//
// The paper queries an octree once per point and names this stage its
// bottleneck (Table 1 "Ngb"; §2: "We expect considerable improvements ... by
// performing batched nearest neighbor queries"). Here the points are copied in
// Morton (Z-curve) order into a nanoflann kd-tree, and the queries run in that
// same order in parallel blocks, so consecutive queries touch the same leaves.
// Each query asks for κ + 1 points (itself included) with a fixed-size result
// set on the stack; results are mapped back to input ids. Deterministic: each
// query's answer depends only on the tree, never on the thread schedule.
#include "framework/points/graph_voronoi.h"
#include "framework/points/graph_internal.h"

#include "framework/error.h"
#include "framework/spatial/knn.h"
#include "framework/util/parallel.h"

#include <nanoflann.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <vector>

namespace arcs {
namespace {

struct SortedCloud {
  std::vector<double> xyz;  // interleaved, Morton order
  std::size_t kdtree_get_point_count() const { return xyz.size() / 3; }
  double kdtree_get_pt(std::size_t i, std::size_t d) const { return xyz[3 * i + d]; }
  template <class Bbox>
  bool kdtree_get_bbox(Bbox&) const {
    return false;
  }
};

using Tree = nanoflann::KDTreeSingleIndexAdaptor<
    nanoflann::L2_Simple_Adaptor<double, SortedCloud, double, std::uint32_t>, SortedCloud, 3,
    std::uint32_t>;

// Insertion-sorts a short row and removes repeats; returns the new length.
int SortUnique(int* a, int len) {
  for (int i = 1; i < len; ++i) {
    const int x = a[i];
    int j = i - 1;
    while (j >= 0 && a[j] > x) {
      a[j + 1] = a[j];
      --j;
    }
    a[j + 1] = x;
  }
  int m = 0;
  for (int i = 0; i < len; ++i)
    if (m == 0 || a[m - 1] != a[i]) a[m++] = a[i];
  return m;
}

}  // namespace

CsrGraph SymmetrizeKnn(const std::vector<int>& knn, int n, int kappa,
                       const std::vector<std::uint8_t>* removed) {
  auto gone = [&](int v) { return removed && (*removed)[v]; };
  auto valid = [&](int i, int t) { return t >= 0 && t != i && !gone(t) && !gone(i); };
  // Reverse lists (j -> i for every i -> j), filled in increasing i, hence
  // sorted without a sort.
  std::vector<std::int64_t> roff(static_cast<std::size_t>(n) + 1, 0);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < kappa; ++j) {
      const int t = knn[static_cast<std::int64_t>(i) * kappa + j];
      if (valid(i, t)) ++roff[t + 1];
    }
  for (int i = 0; i < n; ++i) roff[i + 1] += roff[i];
  std::vector<int> rev(roff[n]);
  {
    std::vector<std::int64_t> pos(roff.begin(), roff.end() - 1);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < kappa; ++j) {
        const int t = knn[static_cast<std::int64_t>(i) * kappa + j];
        if (valid(i, t)) rev[pos[t]++] = i;
      }
  }
  // Own lists, valid entries only, sorted by id (once).
  std::vector<int> own_sorted(knn.size());
  std::vector<int> own_len(n);
  ParallelFor(n, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t v = b; v < e; ++v) {
      int* own = own_sorted.data() + v * kappa;
      int m = 0;
      for (int j = 0; j < kappa; ++j) {
        const int t = knn[v * kappa + j];
        if (valid(static_cast<int>(v), t)) own[m++] = t;
      }
      own_len[v] = SortUnique(own, m);
    }
  });
  // Row v = own list merged with the reverse list, repeats removed. Two
  // passes (length, then fill) so that rows are written in place.
  auto merge_row = [&](int v, int* out) {
    const int* own = own_sorted.data() + static_cast<std::int64_t>(v) * kappa;
    const int len = own_len[v];
    const int* r = rev.data() + roff[v];
    const int rl = static_cast<int>(roff[v + 1] - roff[v]);
    int a = 0, b = 0, c = 0;
    while (a < len || b < rl) {
      int x;
      if (b >= rl || (a < len && own[a] < r[b])) x = own[a++];
      else if (a >= len || r[b] < own[a]) x = r[b++];
      else {
        x = own[a++];
        ++b;
      }
      if (out) out[c] = x;
      ++c;
    }
    return c;
  };
  CsrGraph g;
  g.offsets.assign(static_cast<std::size_t>(n) + 1, 0);
  ParallelFor(n, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t v = b; v < e; ++v) g.offsets[v + 1] = merge_row(static_cast<int>(v), nullptr);
  });
  for (int i = 0; i < n; ++i) g.offsets[i + 1] += g.offsets[i];
  g.adj.resize(g.offsets[n]);
  ParallelFor(n, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t v = b; v < e; ++v) merge_row(static_cast<int>(v), g.adj.data() + g.offsets[v]);
  });
  return g;
}

std::vector<int> KnnListsMorton(const MatrixX3d& P, int kappa, std::vector<int>* order_out,
                                std::vector<double>* mean_dist, double* tree_seconds,
                                bool* has_coincident) {
  std::atomic<bool> coincident{false};
  if (kappa < 1) throw OptionError("kappa = " + std::to_string(kappa) + ": must be >= 1");
  const int n = static_cast<int>(P.rows());
  std::vector<int> knn(static_cast<std::int64_t>(n) * kappa, -1);
  if (mean_dist) mean_dist->assign(n, 0.0);
  std::vector<int>& order = *order_out;
  order = MortonOrder(P);  // position -> input id
  if (n >= 2) {
    SortedCloud cloud;
    cloud.xyz.resize(3 * static_cast<std::size_t>(n));
    for (int s = 0; s < n; ++s)
      for (int d = 0; d < 3; ++d) cloud.xyz[3 * s + d] = P(order[s], d);
    const auto t0 = std::chrono::steady_clock::now();
    Tree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(12));
    if (tree_seconds)
      *tree_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const int want = std::min(kappa + 1, n);
    ParallelFor(
        n,
        [&](std::int64_t b, std::int64_t e) {
          std::vector<std::uint32_t> idx(want);
          std::vector<double> d2(want);
          for (std::int64_t s = b; s < e; ++s) {
            nanoflann::KNNResultSet<double, std::uint32_t, std::uint32_t> res(want);
            res.init(idx.data(), d2.data());
            tree.findNeighbors(res, &cloud.xyz[3 * s], nanoflann::SearchParams());
            const int found = static_cast<int>(res.size());
            int* row = &knn[s * kappa];
            int m = 0;
            double sum = 0;
            for (int j = 0; j < found && m < kappa; ++j) {
              if (idx[j] == static_cast<std::uint32_t>(s)) continue;  // itself
              if (d2[j] == 0.0) coincident.store(true, std::memory_order_relaxed);
              row[m++] = static_cast<int>(idx[j]);
              sum += std::sqrt(d2[j]);
            }
            if (mean_dist) (*mean_dist)[s] = m > 0 ? sum / m : 0.0;
          }
        },
        2048);
  }
  if (has_coincident) *has_coincident = coincident.load();
  return knn;
}

std::vector<int> KnnLists(const MatrixX3d& P, int kappa, std::vector<double>* mean_dist,
                          double* tree_seconds, bool* has_coincident) {
  std::vector<int> order;
  std::vector<double> md;
  const std::vector<int> ks =
      KnnListsMorton(P, kappa, &order, mean_dist ? &md : nullptr, tree_seconds, has_coincident);
  const int n = static_cast<int>(P.rows());
  std::vector<int> knn(ks.size(), -1);
  if (mean_dist) mean_dist->assign(n, 0.0);
  for (int s = 0; s < n; ++s) {
    const int id = order[s];
    for (int j = 0; j < kappa; ++j) {
      const int t = ks[static_cast<std::int64_t>(s) * kappa + j];
      knn[static_cast<std::int64_t>(id) * kappa + j] = t < 0 ? -1 : order[t];
    }
    if (mean_dist) (*mean_dist)[id] = md[s];
  }
  return knn;
}

CsrGraph BuildKnnGraph(const MatrixX3d& P, int kappa, std::vector<double>* mean_dist,
                       const std::vector<std::uint8_t>* removed) {
  const std::vector<int> knn = KnnLists(P, kappa, mean_dist, nullptr);
  return SymmetrizeKnn(knn, static_cast<int>(P.rows()), kappa, removed);
}

}  // namespace arcs
