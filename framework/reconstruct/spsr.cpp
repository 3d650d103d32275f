// arcs' screened Poisson (spsr.h has the method). Layout of this file: the
// octree levels, density and depth, the constraints, the cascadic solve,
// exact evaluation, and the solver's run. Elsewhere: the levels and the
// Solver class in spsr_solver.h, the tracked marching cubes in
// spsr_extract.cpp, the octree's key containers in spsr_keys.h, its finite
// elements and the base level's coarse grids in spsr_fem.h.
#include "framework/reconstruct/spsr.h"

#include "framework/reconstruct/spsr_solver.h"

#include "framework/error.h"
#include "framework/util/parallel.h"

#include <Eigen/Cholesky>

#include <algorithm>
#include <array>
#include <chrono>
#include <functional>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace arcs {

namespace spsr_detail {

void Solver::Normalise(const PointCloud& pc) {
  const int n = pc.Size();
  if (n < 10) throw Error("screened Poisson (arcs): needs at least 10 oriented points, got " + std::to_string(n));
  if (pc.N.rows() != n)
    throw Error("screened Poisson (arcs): needs one normal per point: got " + std::to_string(pc.N.rows()) +
                " normals for " + std::to_string(n) + " points");
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (int i = 0; i < n; ++i) {
    const Vec3 p = pc.P.row(i), q = pc.N.row(i);
    if (!p.allFinite()) throw Error("screened Poisson (arcs): point " + std::to_string(i) + " is not finite");
    if (!q.allFinite() || q.norm() == 0.0)
      throw Error("screened Poisson (arcs): normal " + std::to_string(i) + " is zero or not finite");
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double extent = (hi - lo).maxCoeff();
  if (!(extent > 0)) throw Error("screened Poisson (arcs): all points coincide");
  center_ = 0.5 * (lo + hi);
  side_ = o_.scale * extent;
  p_.resize(n);
  n_.resize(n);
  for (int i = 0; i < n; ++i) {
    p_[i] = (Vec3(pc.P.row(i)) - center_) / side_ + Vec3::Constant(0.5);
    n_[i] = Vec3(pc.N.row(i)).normalized();
  }
}

void Solver::DensityAndDepth() {
  // Tent splats of the samples at the kernel depth k and every coarser level
  // down to full_depth. A sample's density is read at the finest of these
  // levels where it reaches samples_per_node (sparse samples: coarser, as
  // PoissonRecon walks up its tree), so that the estimate is not the
  // sample's own splat alone.
  const int n = static_cast<int>(p_.size());
  const int k = std::max(std::min(F_, D_), D_ - o_.kernel_depth_offset);
  area_.assign(n, 0.0);
  depth_.assign(n, static_cast<double>(F_));
  std::vector<char> done(n, 0);
  double sum = 0;
  for (int e = k; e >= std::min(F_, k); --e) {
    const int res = 1 << e;
    const double he = 1.0 / res;
    KeyMap idx;
    idx.Reserve(static_cast<std::size_t>(n) * 4);
    std::vector<double> W;
    std::vector<std::array<int, 8>> corner(n);
    std::vector<std::array<double, 8>> wt(n);
    for (int s = 0; s < n; ++s) {
      int c[3];
      double w[8];
      CellOf(p_[s], res, c, w);
      for (int q = 0; q < 8; ++q) {
        const Key key = Pack(c[0] + (q & 1), c[1] + ((q >> 1) & 1), c[2] + ((q >> 2) & 1));
        const int id = idx.Insert(key, static_cast<int>(W.size()));
        if (id == static_cast<int>(W.size())) W.push_back(0.0);
        W[id] += w[q];
        corner[s][q] = id;
        wt[s][q] = w[q];
      }
    }
    const bool last = e == std::min(F_, k);
    for (int s = 0; s < n; ++s) {
      if (done[s]) continue;
      double dens = 0;
      for (int q = 0; q < 8; ++q) dens += wt[s][q] * W[corner[s][q]];
      dens = std::max(dens * o_.density_scale, 1e-12);
      if (dens < o_.samples_per_node && !last) continue;
      done[s] = 1;
      area_[s] = he * he / dens;
      sum += area_[s];
      const double ds = e + std::log(dens / o_.samples_per_node) / std::log(4.0);
      depth_[s] = std::clamp(ds, static_cast<double>(F_), static_cast<double>(D_));
    }
  }
  mean_area_ = sum / n;
}

void Solver::BuildLevel(Level& L, std::vector<Key> nodes, bool complete) {
  L.res = 1 << L.d;
  L.h = 1.0 / L.res;
  L.tent = Tent1D{L.h, L.res};
  if (complete) {
    L.nodes.clear();
    for (int z = 0; z <= L.res; ++z)
      for (int y = 0; y <= L.res; ++y)
        for (int x = 0; x <= L.res; ++x) L.nodes.push_back(Pack(x, y, z));
    std::sort(L.nodes.begin(), L.nodes.end());
  } else {
    L.nodes = std::move(nodes);
  }
  L.node_map = BrickIndex::IndexOf(L.nodes);
  const std::size_t nn = L.nodes.size();
  L.nbr.assign(nn * 27, -1);
  L.on_face.assign(nn, 0);
  ParallelFor(static_cast<std::int64_t>(nn), [&](std::int64_t b0, std::int64_t e0) {
    for (std::int64_t i = b0; i < e0; ++i) {
      const int x = KX(L.nodes[i]), y = KY(L.nodes[i]), z = KZ(L.nodes[i]);
      L.on_face[i] = (x == 0 || y == 0 || z == 0 || x == L.res || y == L.res || z == L.res);
    }
    NeighbourRows(L.nodes, L.res, static_cast<std::size_t>(b0), static_cast<std::size_t>(e0), &L.nbr[b0 * 27]);
  }, 2048);
  L.x.assign(nn, 0.0);
  L.U.assign(nn, 0.0);
}

void Solver::BuildTree() {
  const int n = static_cast<int>(p_.size());
  Lmax_ = F_;
  for (int s = 0; s < n; ++s) Lmax_ = std::max(Lmax_, static_cast<int>(std::ceil(depth_[s] - 1e-9)));
  lv_.assign(Lmax_ - F_ + 1, Level{});
  for (int d = F_; d <= Lmax_; ++d) At(d).d = d;
  // fn(d) for the levels d = hi, hi - 1, ..., lo, in parallel (each writes
  // only its own level).
  auto for_levels = [](int lo, int hi, auto&& fn) {
    ParallelFor(hi - lo + 1, [&](std::int64_t l0, std::int64_t l1) {
      for (std::int64_t l = l0; l < l1; ++l) fn(hi - static_cast<int>(l));
    }, 1);
  };
  // Each level's cells as a sorted key list (sets by merging, not hashing).
  std::vector<std::vector<Key>> cells(lv_.size());
  // Cells around every sample up to its depth: the samples' own cells,
  // dilated by one cell.
  for_levels(F_ + 1, Lmax_, [&](int d) {
    const int res = 1 << d;
    std::vector<Key> own;
    Key last = ~Key(0);  // consecutive samples often share a cell
    for (int s = 0; s < n; ++s) {
      if (std::ceil(depth_[s] - 1e-9) < d) continue;
      int c[3];
      double w[8];
      CellOf(p_[s], res, c, w);
      const Key k = Pack(c[0], c[1], c[2]);
      if (k != last) own.push_back(k);
      last = k;
    }
    SortUnique(own);
    cells[d - F_] = DilateCells(own, res);
  });
  // Grading: a cell's parent's neighbours exist.
  for (int d = Lmax_; d >= F_ + 2; --d) {
    const std::vector<Key>& fine = cells[d - F_];
    std::vector<Key> parents(fine.size());
    for (std::size_t i = 0; i < fine.size(); ++i) parents[i] = Pack(KX(fine[i]) >> 1, KY(fine[i]) >> 1, KZ(fine[i]) >> 1);
    SortUnique(parents);
    std::vector<Key>& up = cells[d - 1 - F_];
    up = Union(up, DilateCells(parents, 1 << (d - 1)));
  }
  // The levels' nodes (their cells' corners) and screened samples (the
  // finest level, the largest, starts first).
  for_levels(F_, Lmax_, [&](int d) {
    Level& L = At(d);
    if (d == F_) {
      BuildLevel(L, {}, true);
    } else {
      BuildLevel(L, CellCorners(cells[d - F_]), false);
      std::vector<Key>().swap(cells[d - F_]);
    }
    // Samples screened at this level: those whose own depth reaches it (a
    // sparse sample, e.g. a stray point near denser ones, constrains only
    // the coarse levels it can support, as its normal is splatted there;
    // screened at the finest level it made one-cell bubbles around itself).
    // Their cells exist: the cells around each such sample were made above.
    for (int s = 0; s < n; ++s) {
      if (std::ceil(depth_[s] - 1e-9) < d) continue;
      int c[3];
      double w[8];
      CellOf(p_[s], L.res, c, w);
      // The cell's low corner and, from its stencil row, the other seven.
      const int c0 = L.node_map.Find(Pack(c[0], c[1], c[2]));
      std::array<int, 8> cor;
      std::array<double, 8> ww;
      for (int q = 0; q < 8; ++q) {
        cor[q] = L.nbr[static_cast<std::size_t>(c0) * 27 + 13 + (q & 1) + 3 * ((q >> 1) & 1) + 9 * ((q >> 2) & 1)];
        ww[q] = w[q];
      }
      L.s_idx.push_back(s);
      L.s_corner.push_back(cor);
      L.s_w.push_back(ww);
    }
    if (o_.screen_samples == SpsrOptions::ScreenSamples::kMerged) {
      // The samples by cell (ties by index: a fixed order for the sums).
      std::vector<std::pair<Key, int>> by_cell(L.s_idx.size());
      for (std::size_t t = 0; t < L.s_idx.size(); ++t) {
        int c[3];
        double w[8];
        CellOf(p_[L.s_idx[t]], L.res, c, w);
        by_cell[t] = {Pack(c[0], c[1], c[2]), static_cast<int>(t)};
      }
      std::sort(by_cell.begin(), by_cell.end());
      for (std::size_t b = 0; b < by_cell.size();) {
        std::size_t e = b;
        Vec3 sum = Vec3::Zero();
        for (; e < by_cell.size() && by_cell[e].first == by_cell[b].first; ++e) sum += p_[L.s_idx[by_cell[e].second]];
        const double count = static_cast<double>(e - b);
        const Vec3 mean = sum / count;
        // The mean lies in the samples' cell; its weights there (clamped
        // against rounding at the cell's faces).
        const Key ck = by_cell[b].first;
        const int c[3] = {KX(ck), KY(ck), KZ(ck)};
        double t[3];
        for (int a = 0; a < 3; ++a) t[a] = std::clamp(mean[a] * L.res - c[a], 0.0, 1.0);
        const double root = std::sqrt(count);
        std::array<double, 8> ww;
        for (int q = 0; q < 8; ++q)
          ww[q] = root * ((q & 1) ? t[0] : 1 - t[0]) * ((q & 2) ? t[1] : 1 - t[1]) * ((q & 4) ? t[2] : 1 - t[2]);
        L.m_pos.push_back(mean);
        L.m_count.push_back(count);
        L.m_corner.push_back(L.s_corner[by_cell[b].second]);
        L.m_w.push_back(ww);
        b = e;
      }
    }
  });
}

Vec3 Solver::ProlongVec(const Level& coarse, const std::vector<Vec3>& vc, int x, int y, int z) const {
  return ProlongVecAt(coarse, vc, x, y, z, coarse.node_map.Find(Pack(x >> 1, y >> 1, z >> 1)));
}

Vec3 Solver::ProlongVecAt(const Level& coarse, const std::vector<Vec3>& vc, int x, int y, int z, int base) const {
  int cx[2], cy[2], cz[2];
  double wx[2], wy[2], wz[2];
  const int nx = Parents1D(x, cx, wx), ny = Parents1D(y, cy, wy), nz = Parents1D(z, cz, wz);
  Vec3 v = Vec3::Zero();
  // The parents are the coarse node (cx[0], cy[0], cz[0]) = `base` and its
  // +1 neighbours: when that node is an unknown, its stencil row has their
  // indices (the same the lookups give).
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const int id = base >= 0 ? coarse.nbr[static_cast<std::size_t>(base) * 27 + (i + 1) + 3 * (j + 1) + 9 * (k + 1)]
                                 : coarse.node_map.Find(Pack(cx[i], cy[j], cz[k]));
        if (id >= 0) v += wx[i] * wy[j] * wz[k] * vc[id];
      }
  return v;
}

void Solver::Splat(std::vector<std::vector<Vec3>>& V) {
  V.assign(lv_.size(), {});
  for (int d = F_; d <= Lmax_; ++d) V[d - F_].assign(At(d).nodes.size(), Vec3::Zero());
  for (int d = F_; d <= Lmax_; ++d) {
    Level& L = At(d);
    const double inv_vol = 1.0 / (L.h * L.h * L.h);
    for (std::size_t t = 0; t < L.s_idx.size(); ++t) {
      const int s = L.s_idx[t];
      const double ds = depth_[s];
      const double lo = std::floor(ds);
      double w;
      if (o_.normal_splat == SpsrOptions::NormalSplat::kCeil) {
        if (d != static_cast<int>(std::ceil(ds - 1e-9))) continue;
        w = 1.0;
      } else if (d == static_cast<int>(lo)) {
        w = 1.0 - (ds - lo);
      } else if (d == static_cast<int>(lo) + 1) {
        w = ds - lo;
      } else {
        continue;
      }
      if (w <= 0) continue;
      const Vec3 g = -w * area_[s] * inv_vol * n_[s];
      for (int q = 0; q < 8; ++q) V[d - F_][L.s_corner[t][q]] += L.s_w[t][q] * g;
    }
  }
}

void Solver::Constraints(const std::vector<std::vector<Vec3>>& V, std::vector<std::vector<double>>& b) {
  const int nl = static_cast<int>(lv_.size());
  // G^d applied to a vector field given on the level's nodes; neighbours
  // that are not unknowns take the coarser level's field prolonged (or 0
  // without a coarser level).
  auto apply_g = [&](const Level& L, const std::vector<Vec3>& field, const Level* coarse,
                     const std::vector<Vec3>* coarse_field, std::vector<double>& out) {
    out.assign(L.nodes.size(), 0.0);
    // A field that is zero at every node (and whose coarser field is too)
    // gives zero rows: each row's loop would add nothing to its +0 start.
    // Typical of the complete level, where few samples are splatted.
    auto all_zero = [](const std::vector<Vec3>& f) {
      return std::all_of(f.begin(), f.end(), [](const Vec3& v) { return v.isZero(0); });
    };
    if (all_zero(field) && (!coarse || all_zero(*coarse_field))) return;
    const TentByClass tc(L.tent);
    // Each row on its own (reads only): the same sums at any thread count.
    ParallelFor(static_cast<std::int64_t>(L.nodes.size()), [&](std::int64_t b0, std::int64_t e0) {
      for (std::int64_t i = b0; i < e0; ++i) {
        const int x = KX(L.nodes[i]), y = KY(L.nodes[i]), z = KZ(L.nodes[i]);
        const int cx = AxisClass(x, L.res), cy = AxisClass(y, L.res), cz = AxisClass(z, L.res);
        RowCoarse row_coarse(coarse ? *coarse : L, x, y, z);
        double acc = 0;
        ForStencil(L, static_cast<std::size_t>(i), [&](int o, int a, int bb, int c, int j) {
          Vec3 v;
          if (j >= 0) {
            v = field[j];
          } else if (coarse) {
            v = ProlongVecAt(*coarse, *coarse_field, a, bb, c, row_coarse.Index(a, bb, c));
          } else {
            return;
          }
          if (v.isZero(0)) return;
          const int ox = Ox(o) + 1, oy = Oy(o) + 1, oz = Oz(o) + 1;
          const double mx = tc.M[cx][ox], my = tc.M[cy][oy], mz = tc.M[cz][oz];
          acc += v[0] * tc.D[cx][ox] * my * mz + v[1] * mx * tc.D[cy][oy] * mz + v[2] * mx * my * tc.D[cz][oz];
        });
        out[i] = acc;
      }
    }, 2048);
  };
  // Upward: Vacc^d, the exact level-d representation of V^F + ... + V^d.
  std::vector<std::vector<Vec3>> vacc(nl);
  b.assign(nl, {});
  for (int d = F_; d <= Lmax_; ++d) {
    const Level& L = At(d);
    std::vector<Vec3>& va = vacc[d - F_];
    va = V[d - F_];
    if (d > F_) {
      const Level& C = At(d - 1);
      ParallelFor(static_cast<std::int64_t>(L.nodes.size()), [&](std::int64_t b0, std::int64_t e0) {
        for (std::int64_t i = b0; i < e0; ++i)
          va[i] += ProlongVec(C, vacc[d - 1 - F_], KX(L.nodes[i]), KY(L.nodes[i]), KZ(L.nodes[i]));
      }, 4096);
    }
    apply_g(L, va, d > F_ ? &At(d - 1) : nullptr, d > F_ ? &vacc[d - 1 - F_] : nullptr, b[d - F_]);
  }
  // Downward: contributions of the finer levels' own fields, restricted.
  std::vector<double> fine_next;  // (G^{d+1} V^{d+1} + Fine^{d+1}) on level d+1's nodes
  for (int d = Lmax_; d >= F_; --d) {
    Level& L = At(d);
    std::vector<double> own;
    apply_g(L, V[d - F_], nullptr, nullptr, own);
    std::vector<double> fine(L.nodes.size(), 0.0);
    if (d < Lmax_) {
      const Level& Fl = At(d + 1);
      static const double w1[3] = {0.5, 1.0, 0.5};
      // Row i gathers the finer nodes (2x + u, 2y + v, 2z + w), |u|, |v|,
      // |w| <= 1. Where the finer level is much smaller than this one (the
      // complete level above a sparse one), only the rows some finer node
      // reaches are gathered: a finer coordinate a has the rows a >> 1 to
      // (a + 1) >> 1 on its axis (one when a is even). The others keep their +0,
      // which is what their loops would leave.
      std::vector<std::int64_t> rows_to_do;
      const bool sparse_finer = Fl.nodes.size() * 2 < L.nodes.size();
      if (sparse_finer) {
        rows_to_do = GatherInBlocks<std::int64_t>(
            static_cast<std::int64_t>(Fl.nodes.size()), [&](std::int64_t j, std::vector<std::int64_t>& out) {
              const Key k = Fl.nodes[j];
              for (int z = KZ(k) >> 1; z <= (KZ(k) + 1) >> 1; ++z)
                for (int y = KY(k) >> 1; y <= (KY(k) + 1) >> 1; ++y)
                  for (int x = KX(k) >> 1; x <= (KX(k) + 1) >> 1; ++x)
                    if (const int id = L.node_map.Find(Pack(x, y, z)); id >= 0) out.push_back(id);
            });
        std::sort(rows_to_do.begin(), rows_to_do.end());
        rows_to_do.erase(std::unique(rows_to_do.begin(), rows_to_do.end()), rows_to_do.end());
      }
      const std::int64_t nrows = sparse_finer ? static_cast<std::int64_t>(rows_to_do.size())
                                              : static_cast<std::int64_t>(L.nodes.size());
      auto row_at = [&](std::int64_t r) { return sparse_finer ? rows_to_do[r] : r; };
      ParallelFor(nrows, [&](std::int64_t b0, std::int64_t e0) {
        // The finer nodes around (2x, 2y, 2z) (those keys grow with r).
        std::vector<Key> q(static_cast<std::size_t>(e0 - b0));
        for (std::int64_t r = b0; r < e0; ++r) {
          const std::int64_t i = row_at(r);
          q[r - b0] = Pack(2 * KX(L.nodes[i]), 2 * KY(L.nodes[i]), 2 * KZ(L.nodes[i]));
        }
        std::vector<int> rows(q.size() * 27);
        NeighbourRowsOf(Fl.nodes, Fl.res, q.data(), q.size(), rows.data());
        for (std::int64_t r = b0; r < e0; ++r) {
          const std::int64_t i = row_at(r);
          const int* row = &rows[static_cast<std::size_t>(r - b0) * 27];
          double acc = 0;
          for (int o = 0; o < 27; ++o) {
            const int j = row[o];
            if (j < 0) continue;
            acc += w1[Ox(o) + 1] * w1[Oy(o) + 1] * w1[Oz(o) + 1] * fine_next[j];
          }
          fine[i] = acc;
        }
      }, 2048);
    }
    for (std::size_t i = 0; i < L.nodes.size(); ++i) b[d - F_][i] += fine[i];
    fine_next.assign(L.nodes.size(), 0.0);
    for (std::size_t i = 0; i < L.nodes.size(); ++i) fine_next[i] = own[i] + fine[i];
  }
}

// CG on (K + beta S) x = rhs for the level's own coefficients (L.x holds the
// start and receives the result). Returns the iterations used.
int Solver::SolveLevel(Level& L, const std::vector<double>& rhs, double beta, int max_iters, double tol) {
  const std::int64_t nn = static_cast<std::int64_t>(L.nodes.size());
  // A node's stencil depends only on which faces of the cube it lies on
  // (the tents are cut there): one row per class; class 13, the interior,
  // is kin.
  const ClassStencil kclass = StencilByClass(L.tent);
  const std::array<double, 27>& kin = kclass[13];
  auto stencil_row = [&](std::int64_t i) -> const double* {
    if (!L.on_face[i]) return kin.data();
    const Key k = L.nodes[i];
    return kclass[NodeClass(KX(k), KY(k), KZ(k), L.res)].data();
  };
  const bool complete = nn == std::int64_t(L.res + 1) * (L.res + 1) * (L.res + 1);  // nodes in x-fastest order
  std::array<std::ptrdiff_t, 27> off{};
  for (int o = 0; o < 27; ++o) off[o] = Ox(o) + std::ptrdiff_t(L.res + 1) * (Oy(o) + std::ptrdiff_t(L.res + 1) * Oz(o));
  // Screening as a gather: per node, the (sample slot, weight) pairs touching it.
  const std::vector<std::array<int, 8>>& s_corner = ScreenCorner(L);
  const std::vector<std::array<double, 8>>& s_w = ScreenWeight(L);
  const std::int64_t ns = static_cast<std::int64_t>(s_corner.size());
  std::vector<int> start(nn + 1, 0), slot(static_cast<std::size_t>(ns) * 8);
  std::vector<double> sw(static_cast<std::size_t>(ns) * 8);
  for (std::int64_t t = 0; t < ns; ++t)
    for (int q = 0; q < 8; ++q) ++start[s_corner[t][q] + 1];
  for (std::int64_t i = 0; i < nn; ++i) start[i + 1] += start[i];
  {
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (std::int64_t t = 0; t < ns; ++t)
      for (int q = 0; q < 8; ++q) {
        const int at = fill[s_corner[t][q]]++;
        slot[at] = static_cast<int>(t);
        sw[at] = s_w[t][q];
      }
  }
  std::vector<double> diag(nn);
  ParallelFor(nn, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t i = b; i < e; ++i) {
      double d = stencil_row(i)[13];
      for (int k = start[i]; k < start[i + 1]; ++k) d += beta * sw[k] * sw[k];
      diag[i] = d;
    }
  }, 4096);
  std::vector<double> sval(ns);
  // Row i of (K + beta S) v, the screening read from sval (beta times the
  // samples' values of v, kept current by the caller).
  auto row_product = [&](std::int64_t i, const std::vector<double>& v) {
    double acc = 0;
    const int* nb = &L.nbr[static_cast<std::size_t>(i) * 27];
    if (complete && !L.on_face[i]) {
      // A complete level: every neighbour exists at a fixed offset.
      const double* vi = v.data() + i;
      for (int o = 0; o < 27; ++o) acc += kin[o] * vi[off[o]];
    } else if (!L.on_face[i]) {
      for (int o = 0; o < 27; ++o)
        if (nb[o] >= 0) acc += kin[o] * v[nb[o]];
    } else {
      const double* k = stencil_row(i);
      for (int o = 0; o < 27; ++o)
        if (nb[o] >= 0) acc += k[o] * v[nb[o]];
    }
    if (beta > 0)
      for (int k = start[i]; k < start[i + 1]; ++k) acc += sw[k] * sval[slot[k]];
    return acc;
  };
  // sval = beta times the samples' values of v.
  auto sample_values = [&](const std::vector<double>& v) {
    if (beta > 0)
      ParallelFor(ns, [&](std::int64_t b, std::int64_t e) {
        for (std::int64_t t = b; t < e; ++t) {
          double s = 0;
          for (int q = 0; q < 8; ++q) s += s_w[t][q] * v[s_corner[t][q]];
          sval[t] = beta * s;
        }
      }, 4096);
  };
  // Four interior rows at a time: row_product's sums, term for term in its
  // order (the same bits), as four independent chains of additions (2 % on
  // rfta_bench torus20, session 25).
  auto rows4 = [&](std::int64_t i, const std::vector<double>& v, double* out) {
    double a0 = 0, a1 = 0, a2 = 0, a3 = 0;
    if (complete) {
      const double* v0 = v.data() + i;
      for (int o = 0; o < 27; ++o) {
        const double k = kin[o];
        const std::ptrdiff_t f = off[o];
        a0 += k * v0[f];
        a1 += k * v0[f + 1];
        a2 += k * v0[f + 2];
        a3 += k * v0[f + 3];
      }
    } else {
      // A missing neighbour reads a zero through a select instead of a
      // branch: k * 0 is a signed zero, and adding one to a sum that
      // started at +0 leaves it unchanged (such a sum is never -0), so the
      // sums are those of skipping the term.
      static constexpr double kZero = 0.0;
      const double* vp = v.data();
      auto at = [&](int j) { return j >= 0 ? vp + j : &kZero; };
      const int* nb = &L.nbr[static_cast<std::size_t>(i) * 27];
      for (int o = 0; o < 27; ++o) {
        const double k = kin[o];
        a0 += k * *at(nb[o]);
        a1 += k * *at(nb[27 + o]);
        a2 += k * *at(nb[54 + o]);
        a3 += k * *at(nb[81 + o]);
      }
    }
    if (beta > 0) {
      for (int k = start[i]; k < start[i + 1]; ++k) a0 += sw[k] * sval[slot[k]];
      for (int k = start[i + 1]; k < start[i + 2]; ++k) a1 += sw[k] * sval[slot[k]];
      for (int k = start[i + 2]; k < start[i + 3]; ++k) a2 += sw[k] * sval[slot[k]];
      for (int k = start[i + 3]; k < start[i + 4]; ++k) a3 += sw[k] * sval[slot[k]];
    }
    out[0] = a0, out[1] = a1, out[2] = a2, out[3] = a3;
  };
  auto apply = [&](const std::vector<double>& v, std::vector<double>& out) {
    sample_values(v);
    ParallelFor(nn, [&](std::int64_t b, std::int64_t e) {
      std::int64_t i = b;
      while (i < e) {
        if (i + 4 <= e && !(L.on_face[i] | L.on_face[i + 1] | L.on_face[i + 2] | L.on_face[i + 3])) {
          rows4(i, v, &out[i]);
          i += 4;
        } else {
          out[i] = row_product(i, v);
          ++i;
        }
      }
    }, 4096);
  };
  // Dot products in fixed blocks summed in order: the same at any thread count.
  constexpr std::int64_t kBlock = 8192;
  const std::int64_t nblocks = (nn + kBlock - 1) / kBlock;
  std::vector<double> part(nblocks);
  auto dot = [&](const std::vector<double>& a, const std::vector<double>& b) {
    ParallelFor(nblocks, [&](std::int64_t lo, std::int64_t hi) {
      for (std::int64_t k = lo; k < hi; ++k) {
        double s = 0;
        const std::int64_t e = std::min(nn, (k + 1) * kBlock);
        for (std::int64_t i = k * kBlock; i < e; ++i) s += a[i] * b[i];
        part[k] = s;
      }
    }, 1);
    double s = 0;
    for (double v : part) s += v;
    return s;
  };
  // The complete base level: conjugate gradients preconditioned by a
  // symmetric multigrid V-cycle over the complete grids below it (damped
  // Jacobi, 2 sweeps before and after, a dense Cholesky solve at level 2):
  // the screening is weak where samples are few, the system nearly the
  // Neumann Laplacian's, on which Jacobi-CG needed 100-130 steps at any n.
  // The finer levels are local and keep Jacobi.
  const bool mg = L.d == F_ && F_ >= 3 && complete;
  std::vector<CoarseGrid> grids;  // levels 2 .. F-1
  Eigen::LLT<Eigen::MatrixXd> coarsest;
  if (mg) {
    // Levels 2 .. F-1, each built on its own (in parallel).
    grids.resize(static_cast<std::size_t>(F_ - 2));
    ParallelFor(F_ - 2, [&](std::int64_t b0, std::int64_t e0) {
      for (std::int64_t c = b0; c < e0; ++c)
        if (Merged())
          grids[c].Build(static_cast<int>(c) + 2, L.m_pos, nullptr, &L.m_count, beta);
        else
          grids[c].Build(static_cast<int>(c) + 2, p_, &L.s_idx, nullptr, beta);
    }, 1);
    const CoarseGrid& g = grids.front();
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(g.N(), g.N());
    const int r1 = g.res + 1;
    for (int i = 0; i < g.N(); ++i)
      for (int o = 0; o < 27; ++o)
        if (g.coef[static_cast<std::size_t>(i) * 27 + o] != 0)
          A(i, i + Ox(o) + r1 * (Oy(o) + r1 * Oz(o))) += g.coef[static_cast<std::size_t>(i) * 27 + o];
    // Unscreened (beta 0) the Neumann operator is singular: a tiny shift
    // keeps the preconditioner definite.
    A.diagonal().array() += 1e-10 * A.diagonal().maxCoeff();
    coarsest.compute(A);
  }
  constexpr double kOmega = 0.8;  // Jacobi damping (the Q1 stencil's D^-1 K spans about [0, 1.5])
  // f(i) for i in [0, n), in parallel (elementwise: the same bits).
  auto each = [](std::int64_t n, auto&& f) {
    ParallelFor(n, [&](std::int64_t b, std::int64_t e) {
      for (std::int64_t i = b; i < e; ++i) f(i);
    }, 4096);
  };
  // e = V(r) on coarse grid k (index into grids), r and e dense.
  std::function<void(std::size_t, const std::vector<double>&, std::vector<double>&)> vcycle =
      [&](std::size_t k, const std::vector<double>& rr, std::vector<double>& e) {
        const CoarseGrid& g = grids[k];
        if (k == 0) {
          const Eigen::VectorXd sol = coarsest.solve(Eigen::Map<const Eigen::VectorXd>(rr.data(), g.N()));
          e.assign(sol.data(), sol.data() + g.N());
          return;
        }
        std::vector<double> ae, res(g.N()), rc, ec;
        e.assign(g.N(), 0.0);
        each(g.N(), [&](std::int64_t i) { e[i] = kOmega * rr[i] / g.Diag(i); });
        g.Apply(e, ae);
        each(g.N(), [&](std::int64_t i) { e[i] += kOmega * (rr[i] - ae[i]) / g.Diag(i); });
        g.Apply(e, ae);
        each(g.N(), [&](std::int64_t i) { res[i] = rr[i] - ae[i]; });
        Restrict(grids[k - 1].res, res, rc);
        vcycle(k - 1, rc, ec);
        ProlongAdd(grids[k - 1].res, ec, e);
        for (int sweep = 0; sweep < 2; ++sweep) {
          g.Apply(e, ae);
          each(g.N(), [&](std::int64_t i) { e[i] += kOmega * (rr[i] - ae[i]) / g.Diag(i); });
        }
      };
  // z = V(r) on the base level itself (its own parallel operator).
  std::vector<double> ae(nn), res(nn), rc, ec;
  std::function<void(const std::vector<double>&, std::vector<double>&)> precondition =
      [&](const std::vector<double>& rr, std::vector<double>& zz) {
    if (!mg) {
      each(nn, [&](std::int64_t i) { zz[i] = rr[i] / diag[i]; });
      return;
    }
    each(nn, [&](std::int64_t i) { zz[i] = kOmega * rr[i] / diag[i]; });
    apply(zz, ae);
    each(nn, [&](std::int64_t i) { zz[i] += kOmega * (rr[i] - ae[i]) / diag[i]; });
    apply(zz, ae);
    each(nn, [&](std::int64_t i) { res[i] = rr[i] - ae[i]; });
    Restrict(grids.back().res, res, rc);
    vcycle(grids.size() - 1, rc, ec);
    ProlongAdd(grids.back().res, ec, zz);
    for (int sweep = 0; sweep < 2; ++sweep) {
      apply(zz, ae);
      each(nn, [&](std::int64_t i) { zz[i] += kOmega * (rr[i] - ae[i]) / diag[i]; });
    }
  };
  // The finer levels' Gauss-Seidel (SpsrOptions::FineSolver): eight colours
  // by node parity. A 27-point stencil joins nodes at most one apart on each
  // axis, and a sample's eight corners are one cell's, so no two nodes of a
  // colour are coupled and each sample touches one node of each colour: a
  // colour updates in parallel, each node writing only its own samples'
  // values, and the result does not depend on the thread count.
  const SpsrOptions::FineSolver mode = mg ? SpsrOptions::FineSolver::kCgJacobi : o_.fine_solver;
  std::array<std::vector<int>, 8> colour;
  if (mode != SpsrOptions::FineSolver::kCgJacobi)
    for (std::int64_t i = 0; i < nn; ++i) {
      const Key k = L.nodes[i];
      colour[(KX(k) & 1) | (KY(k) & 1) << 1 | (KZ(k) & 1) << 2].push_back(static_cast<int>(i));
    }
  // One colour's update of zz towards A zz = rr; sval holds beta times the
  // samples' values of zz and is kept so.
  auto gs_colour = [&](int c, const std::vector<double>& rr, std::vector<double>& zz) {
    const std::vector<int>& list = colour[c];
    ParallelFor(static_cast<std::int64_t>(list.size()), [&](std::int64_t b, std::int64_t e) {
      for (std::int64_t k = b; k < e; ++k) {
        const int i = list[k];
        const double delta = (rr[i] - row_product(i, zz)) / diag[i];
        zz[i] += delta;
        if (beta > 0)
          for (int t = start[i]; t < start[i + 1]; ++t) sval[slot[t]] += beta * sw[t] * delta;
      }
    }, 2048);
  };
  auto relative_residual = [&]() {
    std::vector<double> ax(nn), rr(nn);
    apply(L.x, ax);
    for (std::int64_t i = 0; i < nn; ++i) rr[i] = rhs[i] - ax[i];
    const double bn = std::sqrt(dot(rhs, rhs));
    return bn > 0 ? std::sqrt(dot(rr, rr)) / bn : 0.0;
  };
  if (mode == SpsrOptions::FineSolver::kGaussSeidel) {
    // PoissonRecon's relaxation: sweeps over the colours in order, from the
    // start L.x holds.
    sample_values(L.x);
    for (int sweep = 0; sweep < o_.gs_iters; ++sweep)
      for (int c = 0; c < 8; ++c) gs_colour(c, rhs, L.x);
    // Measured at the finest level only (what SpsrInfo reports): one product more.
    last_residual_ = L.d == Lmax_ ? relative_residual() : 0.0;
    return o_.gs_iters;
  }
  if (mode == SpsrOptions::FineSolver::kCgGaussSeidel) {
    // Symmetric Gauss-Seidel from zero: colours 0..7, then 6..0 (colour 7
    // would not move again). (D+L) D^-1 (D+U) with L, U the couplings to
    // earlier and later colours: symmetric positive definite.
    precondition = [&](const std::vector<double>& rr, std::vector<double>& zz) {
      std::fill(zz.begin(), zz.end(), 0.0);
      std::fill(sval.begin(), sval.end(), 0.0);
      for (int c = 0; c < 8; ++c) gs_colour(c, rr, zz);
      for (int c = 6; c >= 0; --c) gs_colour(c, rr, zz);
    };
  }
  const bool pre_each = mg || mode == SpsrOptions::FineSolver::kCgGaussSeidel;
  std::vector<double> r(nn), z(nn), p(nn), q(nn);
  apply(L.x, q);
  for (std::int64_t i = 0; i < nn; ++i) r[i] = rhs[i] - q[i];
  const double bnorm = std::sqrt(dot(rhs, rhs));
  last_residual_ = 0;
  if (bnorm == 0) return 0;
  precondition(r, z);
  p = z;
  double rz = dot(r, z);
  int it = 0;
  for (; it < max_iters; ++it) {
    if (std::sqrt(dot(r, r)) <= tol * bnorm) break;
    apply(p, q);
    const double pq = dot(p, q);
    if (!(pq > 0)) break;
    const double alpha = rz / pq;
    ParallelFor(nn, [&](std::int64_t b, std::int64_t e) {
      for (std::int64_t i = b; i < e; ++i) {
        L.x[i] += alpha * p[i];
        r[i] -= alpha * q[i];
        if (!pre_each) z[i] = r[i] / diag[i];
      }
    }, 8192);
    if (pre_each) precondition(r, z);
    const double rz2 = dot(r, z);
    const double beta_cg = rz2 / rz;
    rz = rz2;
    ParallelFor(nn, [&](std::int64_t b, std::int64_t e) {
      for (std::int64_t i = b; i < e; ++i) p[i] = z[i] + beta_cg * p[i];
    }, 8192);
  }
  last_residual_ = std::sqrt(dot(r, r)) / bnorm;
  return it;
}

// χ at node k of `level` (any grid node: unknowns read U, others are
// prolonged from the coarser level, memoised).
double Solver::ValueWith(int level, Key k, Memo& memo) const {
  for (;;) {
    const Level& L = At(level);
    const int id = L.node_map.Find(k);
    if (id >= 0) return L.U[id];
    if (level == F_) return 0.0;  // cannot happen: level F is complete
    // A node with even coordinates has one parent, of weight 1: its value is
    // the parent's (the same bits as ParentSum's single term), not memoised.
    const int x = KX(k), y = KY(k), z = KZ(k);
    if (((x | y | z) & 1) != 0) break;
    k = Pack(x >> 1, y >> 1, z >> 1);
    --level;
  }
  KeyMap& mm = memo.map[level - F_];
  std::vector<double>& mv = memo.val[level - F_];
  const int m = mm.Find(k);
  if (m >= 0) return mv[m];
  const double v = ParentSum<double>(KX(k), KY(k), KZ(k), [&](int a, int b, int c) {
    return ValueWith(level - 1, Pack(a, b, c), memo);
  });
  mm.Insert(k, static_cast<int>(mv.size()));
  mv.push_back(v);
  return v;
}

double Solver::ChiWith(const Vec3& p, Memo& memo) const {
  const int res = 1 << Lmax_;
  int c[3];
  double w[8];
  CellOf(p, res, c, w);
  double v = 0;
  for (int q = 0; q < 8; ++q)
    v += w[q] * ValueWith(Lmax_, Pack(c[0] + (q & 1), c[1] + ((q >> 1) & 1), c[2] + ((q >> 2) & 1)), memo);
  return v;
}


}  // namespace spsr_detail

using spsr_detail::Solver;

struct SpsrWarmStart {
  int full_depth = 0;
  std::vector<std::vector<spsr_keys::Key>> nodes;   // per level from full_depth
  std::vector<std::vector<double>> x;
};

Mesh Solver::Run(const PointCloud& pc, std::shared_ptr<SpsrWarmStart>* warm, SpsrInfo* info) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  D_ = o_.depth;
  F_ = std::min(o_.full_depth, D_);
  Normalise(pc);
  DensityAndDepth();
  BuildTree();
  std::vector<std::vector<Vec3>> V;
  Splat(V);
  std::vector<std::vector<double>> b;
  Constraints(V, b);
  V.clear();
  memo_ = Memo(lv_.size());
  const SpsrWarmStart* w = (warm && *warm && (*warm)->full_depth == F_) ? warm->get() : nullptr;
  int total_iters = 0;
  long long unknowns = 0;
  for (int d = F_; d <= Lmax_; ++d) {
    Level& L = At(d);
    unknowns += static_cast<long long>(L.nodes.size());
    const double beta = o_.point_weight * mean_area_ * std::pow(2.0, o_.screen_depth_exponent * d);
    std::vector<double> P(L.nodes.size(), 0.0);
    std::vector<double> rhs = b[d - F_];
    if (d > F_) {
      // The coarser solution at this level's nodes, then rhs -= K P
      // (neighbours that are not unknowns are prolonged on the fly); in
      // parallel, each block with its own memo of prolonged values (the same
      // bits as one serial memo).
      const std::int64_t nn = static_cast<std::int64_t>(L.nodes.size());
      // The parents are the coarser node (x/2, y/2, z/2) rounded down and its
      // +1 neighbours: when it is an unknown, its stencil row has their
      // indices, and unknowns read U (what ValueWith returns for them).
      const Level& C = At(d - 1);
      // base: the unknown index of the coarser node (x >> 1, y >> 1, z >> 1), or -1.
      auto block_coarse_at = [&](Memo& memo, int x, int y, int z, int base) {
        return ParentSum<double>(x, y, z, [&](int a, int bb, int c) {
          if (base >= 0) {
            const int o = (a - (x >> 1) + 1) + 3 * (bb - (y >> 1) + 1) + 9 * (c - (z >> 1) + 1);
            const int id = C.nbr[static_cast<std::size_t>(base) * 27 + o];
            if (id >= 0) return C.U[id];
          }
          return ValueWith(d - 1, Pack(a, bb, c), memo);
        });
      };
      ParallelFor(nn, [&](std::int64_t b0, std::int64_t e0) {
        Memo memo(lv_.size());
        for (std::int64_t i = b0; i < e0; ++i) {
          const int x = KX(L.nodes[i]), y = KY(L.nodes[i]), z = KZ(L.nodes[i]);
          P[i] = block_coarse_at(memo, x, y, z, C.node_map.Find(Pack(x >> 1, y >> 1, z >> 1)));
        }
      }, 4096);
      const ClassStencil kclass = StencilByClass(L.tent);
      ParallelFor(nn, [&](std::int64_t b0, std::int64_t e0) {
        Memo memo(lv_.size());
        for (std::int64_t i = b0; i < e0; ++i) {
          const int x = KX(L.nodes[i]), y = KY(L.nodes[i]), z = KZ(L.nodes[i]);
          const double* k = kclass[NodeClass(x, y, z, L.res)].data();
          RowCoarse row_coarse(C, x, y, z);
          double acc = 0;
          ForStencil(L, static_cast<std::size_t>(i), [&](int o, int a, int bb, int c, int j) {
            const double pv = j >= 0 ? P[j] : block_coarse_at(memo, a, bb, c, row_coarse.Index(a, bb, c));
            if (pv == 0) return;
            acc += pv * k[o];
          });
          rhs[i] -= acc;
        }
      }, 4096);
      if (beta > 0) {
        const std::vector<std::array<int, 8>>& sc = ScreenCorner(L);
        const std::vector<std::array<double, 8>>& sw = ScreenWeight(L);
        for (std::size_t s = 0; s < sc.size(); ++s) {
          double chi = 0;
          for (int q = 0; q < 8; ++q) chi += sw[s][q] * P[sc[s][q]];
          for (int q = 0; q < 8; ++q) rhs[sc[s][q]] -= beta * sw[s][q] * chi;
        }
      }
    }
      std::fill(L.x.begin(), L.x.end(), 0.0);
    if (w && d - F_ < static_cast<int>(w->nodes.size())) {
      const std::vector<Key>& wk = w->nodes[d - F_];
      const std::vector<double>& wx = w->x[d - F_];
      // Both sorted: merge.
      std::size_t j = 0;
      for (std::size_t i = 0; i < L.nodes.size(); ++i) {
        while (j < wk.size() && wk[j] < L.nodes[i]) ++j;
        if (j < wk.size() && wk[j] == L.nodes[i]) L.x[i] = wx[j];
      }
    }
    const bool coarse = d == F_;
    total_iters += SolveLevel(L, rhs, beta, coarse ? std::max(200, o_.iters) : o_.iters,
                              coarse ? o_.base_accuracy : o_.accuracy);
    for (std::size_t i = 0; i < L.nodes.size(); ++i) L.U[i] = P[i] + L.x[i];
    ctx_.CheckStop();
  }
  const auto t1 = Clock::now();
  double vsum = 0;
  const bool by_count = o_.iso_weight == SpsrOptions::IsoWeight::kCount;
  {
    // χ at the samples in parallel (each block with its own memo: the same
    // values), summed in sample order.
    std::vector<double> chi(p_.size());
    ParallelFor(static_cast<std::int64_t>(p_.size()), [&](std::int64_t b0, std::int64_t e0) {
      Memo memo(lv_.size());
      for (std::int64_t s = b0; s < e0; ++s) chi[s] = ChiWith(p_[s], memo);
    }, 1024);
    for (std::size_t s = 0; s < p_.size(); ++s) vsum += (by_count ? 1.0 : area_[s]) * chi[s];
  }
  const double area = mean_area_ * static_cast<double>(p_.size());
  const double iso = by_count ? vsum / static_cast<double>(p_.size()) : vsum / area;
  Mesh m = Extract(iso);
  const auto t2 = Clock::now();
  if (warm) {
    auto nw = std::make_shared<SpsrWarmStart>();
    nw->full_depth = F_;
    for (Level& L : lv_) {
      nw->nodes.push_back(std::move(L.nodes));
      nw->x.push_back(std::move(L.x));
    }
    *warm = std::move(nw);
  }
  if (info) {
    info->depth = Lmax_;
    info->extract_depth = extract_level_;
    info->islands_removed = islands_;
    info->carved_nodes = carved_;
    info->carve_only_components = carve_only_;
    info->iso_value = iso;
    info->area = area;
    info->unknowns = unknowns;
    info->cg_iterations = total_iters;
    info->final_residual = last_residual_;
    info->warm_started = w != nullptr;
    info->solve_s = std::chrono::duration<double>(t1 - t0).count();
    info->extract_s = std::chrono::duration<double>(t2 - t1).count();
  }
  return m;
}

Mesh ReconstructSpsr(const PointCloud& oriented, const SpsrOptions& options, const Context& ctx,
                     std::shared_ptr<SpsrWarmStart>* warm, SpsrInfo* info) {
  ARCS_CHECK_OPTION(options.depth >= 2 && options.depth <= 12, "depth", options.depth, "an integer in [2, 12]");
  ARCS_CHECK_OPTION(options.full_depth >= 1 && options.full_depth <= 8, "full_depth", options.full_depth,
                    "an integer in [1, 8]");
  ARCS_CHECK_OPTION(std::isfinite(options.scale) && options.scale >= 1.01 && options.scale <= 16.0, "scale",
                    options.scale, "in [1.01, 16]");
  ARCS_CHECK_OPTION(std::isfinite(options.samples_per_node) && options.samples_per_node >= 0.5 &&
                        options.samples_per_node <= 100.0,
                    "samples_per_node", options.samples_per_node, "in [0.5, 100]");
  ARCS_CHECK_OPTION(std::isfinite(options.point_weight) && options.point_weight >= 0 && options.point_weight <= 1e6,
                    "point_weight", options.point_weight, "in [0, 1e6]");
  ARCS_CHECK_OPTION(options.iters >= 1 && options.iters <= 10000, "iters", options.iters, "in [1, 10000]");
  ARCS_CHECK_OPTION(options.accuracy > 0 && options.accuracy < 1, "accuracy", options.accuracy, "in (0, 1)");
  ARCS_CHECK_OPTION(options.base_accuracy > 0 && options.base_accuracy < 1, "base_accuracy", options.base_accuracy,
                    "in (0, 1)");
  ARCS_CHECK_OPTION(options.gs_iters >= 1 && options.gs_iters <= 10000, "gs_iters", options.gs_iters,
                    "in [1, 10000]");
  ARCS_CHECK_OPTION(options.kernel_depth_offset >= 0 && options.kernel_depth_offset <= 6, "kernel_depth_offset",
                    options.kernel_depth_offset, "in [0, 6]");
  ARCS_CHECK_OPTION(std::isfinite(options.extract_max_cell) && options.extract_max_cell >= 0, "extract_max_cell",
                    options.extract_max_cell, "finite and >= 0");
  ARCS_CHECK_OPTION(std::isfinite(options.density_scale) && options.density_scale >= 0.1 &&
                        options.density_scale <= 10.0,
                    "density_scale", options.density_scale, "in [0.1, 10]");
  Solver solver(options, ctx);
  return solver.Run(oriented, warm, info);
}

}  // namespace arcs
