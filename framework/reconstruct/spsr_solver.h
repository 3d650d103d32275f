// The octree solver behind arcs' screened Poisson (spsr.h has the method):
// its levels and the Solver class, shared by spsr.cpp (the octree, density
// and depth, the constraints, the cascadic solve, exact evaluation) and
// spsr_extract.cpp (tracked marching cubes). Internal to
// framework/reconstruct, as spsr_keys.h and spsr_fem.h.
#pragma once

#include "framework/reconstruct/spsr.h"
#include "framework/reconstruct/spsr_fem.h"
#include "framework/reconstruct/spsr_keys.h"
#include "framework/util/parallel.h"

#include <array>
#include <cstddef>
#include <memory>
#include <vector>

namespace arcs::spsr_detail {

using namespace spsr_keys;  // Key, Pack, KeyMap, NodeCache, BrickIndex, the sorted-set helpers
using namespace spsr_fem;   // tents, stencils, CellOf, ParentSum, the coarse grids

struct Level {
  int d = 0, res = 0;
  double h = 0;
  Tent1D tent{};
  std::vector<Key> nodes;  // sorted unknowns (corners of existing cells)
  BrickIndex node_map;
  std::vector<int> nbr;    // 27 per node: index of the neighbour unknown or -1
  std::vector<unsigned char> on_face;  // node touches the cube's boundary
  // Samples whose cell exists at this level: index, corner unknowns, weights.
  std::vector<int> s_idx;
  std::vector<std::array<int, 8>> s_corner;
  std::vector<std::array<double, 8>> s_w;
  // With SpsrOptions::ScreenSamples::kMerged, the points that screen this
  // level: one per cell holding samples, at their mean (m_pos), its corner
  // unknowns, and its trilinear weights times sqrt(count), so that the
  // screening term count * χ(mean)^2 has the form of a sample's. Empty with
  // kEach: the samples above screen.
  std::vector<Vec3> m_pos;
  std::vector<double> m_count;
  std::vector<std::array<int, 8>> m_corner;
  std::vector<std::array<double, 8>> m_w;
  std::vector<double> x, U;  // own coefficients; accumulated solution χ_{<=d} at the nodes
};

// Calls fn(o, a, b, c, j) for the 27 stencil neighbours (a, b, c) of node i
// that lie in the cube; j is the neighbour's unknown index or -1.
// The items fn(i, out) appends to `out` for i in [0, n), gathered in
// parallel by fixed blocks of 2048 and concatenated in block order (the same
// list at any thread count).
template <class T, class Fn>
std::vector<T> GatherInBlocks(std::int64_t n, Fn&& fn) {
  constexpr std::int64_t kBlock = 2048;
  const std::int64_t nb = (n + kBlock - 1) / kBlock;
  std::vector<std::vector<T>> part(static_cast<std::size_t>(nb));
  ParallelFor(nb, [&](std::int64_t b0, std::int64_t e0) {
    for (std::int64_t blk = b0; blk < e0; ++blk)
      for (std::int64_t i = blk * kBlock; i < std::min(n, (blk + 1) * kBlock); ++i) fn(i, part[blk]);
  }, 1);
  std::vector<T> out;
  for (const auto& v : part) out.insert(out.end(), v.begin(), v.end());
  return out;
}

template <class Fn>
inline void ForStencil(const Level& L, std::size_t i, Fn&& fn) {
  const int x = KX(L.nodes[i]), y = KY(L.nodes[i]), z = KZ(L.nodes[i]);
  for (int o = 0; o < 27; ++o) {
    const int a = x + Ox(o), b = y + Oy(o), c = z + Oz(o);
    if (a < 0 || b < 0 || c < 0 || a > L.res || b > L.res || c > L.res) continue;
    fn(o, a, b, c, L.nbr[i * 27 + o]);
  }
}

// The coarser level's indices for one fine row (x, y, z): of coarse node
// (a >> 1, b >> 1, c >> 1) for each fine node (a, b, c) of the row's
// stencil. That node is at most one apart on each axis from the row's own
// coarse node (x >> 1, y >> 1, z >> 1), so when the latter is an unknown
// its stencil row holds the index (what node_map.Find gives, without the
// lookup); it is looked up once, when first needed.
class RowCoarse {
 public:
  RowCoarse(const Level& C, int x, int y, int z) : C_(C), px_(x >> 1), py_(y >> 1), pz_(z >> 1) {}
  int Index(int a, int b, int c) {
    if (base_ == -2) base_ = C_.node_map.Find(Pack(px_, py_, pz_));
    if (base_ >= 0)
      return C_.nbr[static_cast<std::size_t>(base_) * 27 + ((a >> 1) - px_ + 1) + 3 * ((b >> 1) - py_ + 1) +
                    9 * ((c >> 1) - pz_ + 1)];
    return C_.node_map.Find(Pack(a >> 1, b >> 1, c >> 1));
  }

 private:
  const Level& C_;
  int px_, py_, pz_;
  int base_ = -2;  // not looked up yet
};

class Solver {
 public:
  Solver(const SpsrOptions& o, const Context& ctx) : o_(o), ctx_(ctx) {}

  Mesh Run(const PointCloud& pc, std::shared_ptr<SpsrWarmStart>* warm, SpsrInfo* info);

 private:
  void Normalise(const PointCloud& pc);
  void DensityAndDepth();
  void BuildTree();
  // The level's unknowns: `nodes` (sorted, distinct), or every node of a
  // complete level; their index, stencil neighbours and faces.
  void BuildLevel(Level& L, std::vector<Key> nodes, bool complete);
  void Splat(std::vector<std::vector<Vec3>>& V);
  void Constraints(const std::vector<std::vector<Vec3>>& V, std::vector<std::vector<double>>& b);
  Vec3 ProlongVec(const Level& coarse, const std::vector<Vec3>& vc, int x, int y, int z) const;
  // The same with `base`, the unknown index of coarse node (x >> 1, y >> 1,
  // z >> 1) or -1, given.
  Vec3 ProlongVecAt(const Level& coarse, const std::vector<Vec3>& vc, int x, int y, int z, int base) const;
  int SolveLevel(Level& L, const std::vector<double>& b, double beta, int max_iters, double tol);
  // The points that screen level L (SpsrOptions::screen_samples): their
  // corner unknowns and weights.
  bool Merged() const { return o_.screen_samples == SpsrOptions::ScreenSamples::kMerged; }
  const std::vector<std::array<int, 8>>& ScreenCorner(const Level& L) const { return Merged() ? L.m_corner : L.s_corner; }
  const std::vector<std::array<double, 8>>& ScreenWeight(const Level& L) const { return Merged() ? L.m_w : L.s_w; }
  // Prolonged values of nodes that are not unknowns, per level: the solver's
  // own, or a parallel block's.
  struct Memo {
    std::vector<KeyMap> map;
    std::vector<std::vector<double>> val;
    Memo() = default;
    explicit Memo(std::size_t levels) : map(levels), val(levels) {}
  };
  double Value(int level, Key k) { return ValueWith(level, k, memo_); }
  // χ at level-`level` grid node k with the memo given (values of nodes that
  // are not unknowns, per level): a pure function of the solution, so any
  // memo (the solver's, or a thread's own) gives the same bits.
  double ValueWith(int level, Key k, Memo& memo) const;
  int extract_level_ = 0;
  int islands_ = 0;
  long long carved_ = 0;
  long long carve_only_ = 0;  // closed components made by the carving field alone, dropped
  double last_residual_ = 0;  // SolveLevel's relative residual at its end
  // χ at p (unit cube), trilinear on the finest level's grid.
  double ChiWith(const Vec3& p, Memo& memo) const;
  Mesh Extract(double iso);

  const SpsrOptions& o_;
  const Context& ctx_;
  int F_ = 5, D_ = 10, Lmax_ = 5;
  Vec3 center_;
  double side_ = 1;
  std::vector<Vec3> p_, n_;  // unit-cube points, unit normals
  std::vector<double> area_, depth_;
  double mean_area_ = 0;
  std::vector<Level> lv_;  // index d - F
  Memo memo_;
  Level& At(int d) { return lv_[d - F_]; }
  const Level& At(int d) const { return lv_[d - F_]; }
};

}  // namespace arcs::spsr_detail
