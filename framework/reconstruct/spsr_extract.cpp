// Tracked marching cubes on the screened Poisson's solution (Solver::Extract,
// spsr_solver.h): the extraction level, node values memoised per brick, the
// seeds (the samples' cells and the sign changes along the complete level's
// edges), and breadth-first rounds of cells with their values prefetched in
// parallel.
#include "framework/reconstruct/spsr_solver.h"

#include "framework/geometry/marching_cubes.h"
#include "framework/geometry/submesh.h"
#include "framework/spatial/topology.h"
#include "framework/util/parallel.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace arcs::spsr_detail {

Mesh Solver::Extract(double iso) {
  // The extraction level: the samples' depth at the chosen quantile (the
  // octree's leaves are at the samples' depths, where PoissonRecon extracts).
  int L = Lmax_;
  if (o_.extract_quantile < 1.0) {
    std::vector<double> ds = depth_;
    const std::size_t q = std::min(ds.size() - 1, static_cast<std::size_t>(o_.extract_quantile * (ds.size() - 1) + 0.5));
    std::nth_element(ds.begin(), ds.begin() + static_cast<std::ptrdiff_t>(q), ds.end());
    L = std::clamp(static_cast<int>(std::ceil(ds[q] - 1e-9)), F_, Lmax_);
  }
  if (o_.extract_max_cell > 0) {
    // Cells of level l have side side_ / 2^l (input units).
    const int coarsest = static_cast<int>(std::ceil(std::log2(side_ / o_.extract_max_cell) - 1e-9));
    L = std::clamp(std::min(L, coarsest), F_, Lmax_);
  }
  extract_level_ = L;
  const int res = 1 << L;
  const int up = Lmax_ - L;  // grid nodes of level L are nodes of the finest level
  auto g = [&](int x, int y, int z) { return iso - Value(Lmax_, Pack(x << up, y << up, z << up)); };  // < 0 inside
  // Node values of the extraction grid, cached (raw), and as marching cubes
  // sees them: a node whose side of the iso-value differs from all six of
  // its face neighbours' is an island below the grid's resolution (it makes
  // a closed component of 8 triangles; stray tuning points inside a solid
  // made such voids), so with remove_node_islands it takes the mean of
  // those neighbours.
  // The complete level's nodes on a dense lattice (the seed search below
  // reads all of them), the rest in bricks.
  NodeCache<double> rmap(L - F_, (1 << F_) + 1), gmap(L - F_, (1 << F_) + 1);
  auto R = [&](int x, int y, int z) {
    const Key k = Pack(x, y, z);
    if (const double* known = rmap.Lookup(k)) return *known;
    const double v = g(x, y, z);
    rmap.Set(k, v);
    return v;
  };
  // The value marching cubes sees at node (x, y, z) from the raw values
  // `raw` gives; *island: the island rule replaced it.
  auto seen = [&](int x, int y, int z, auto&& raw, bool* island) {
    double v = raw(x, y, z);
    *island = false;
    if (o_.remove_node_islands) {
      static const int nb[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
      bool all_other = true;
      double mean = 0;
      int count = 0;
      for (const auto& o : nb) {
        const int a = x + o[0], b = y + o[1], c = z + o[2];
        if (a < 0 || b < 0 || c < 0 || a > res || b > res || c > res) continue;
        const double u = raw(a, b, c);
        if ((u < 0) == (v < 0)) {
          all_other = false;
          break;
        }
        mean += u;
        ++count;
      }
      if (all_other && count == 6) {
        v = mean / count;
        *island = true;
      }
    }
    return v;
  };
  auto G = [&](int x, int y, int z) {
    const Key k = Pack(x, y, z);
    if (const double* known = gmap.Lookup(k)) return *known;
    bool island;
    const double v = seen(x, y, z, R, &island);
    islands_ += island;
    gmap.Set(k, v);
    return v;
  };
  // The carving field (SpsrOptions::carve) at the nodes gmap holds, in cmap
  // (empty without carving): a node is inside iff χ says so (G < 0) and the
  // field does not (c <= 0). cmap holds c exactly wherever c > -edge_len
  // (one finest cell) and c < edge_len, elsewhere a value as far on the same
  // side: a crossed edge whose ends disagree on c > 0 then places its
  // vertex from the values at hand.
  const bool carving = static_cast<bool>(o_.carve);
  NodeCache<double> cmap(L - F_, (1 << F_) + 1);
  auto node_pos = [&](Key k) {
    return Vec3(((KX(k) + 0.0) / res - 0.5) * side_ + center_[0], ((KY(k) + 0.0) / res - 0.5) * side_ + center_[1],
                ((KZ(k) + 0.0) / res - 0.5) * side_ + center_[2]);
  };
  const double edge_len = side_ / res;
  // The field at the nodes `keys` (sorted, unique, none in cmap yet).
  auto eval_carve = [&](const std::vector<Key>& keys) {
    if (!carving || keys.empty()) return;
    std::vector<Vec3> x(keys.size());
    for (std::size_t i = 0; i < keys.size(); ++i) x[i] = node_pos(keys[i]);
    std::vector<double> c;
    o_.carve.near(x, edge_len, c);
    if (c.size() != keys.size()) throw Error("screened Poisson: the carving field returned the wrong count");
    for (std::size_t i = 0; i < keys.size(); ++i) carved_ += c[i] > 0 && *gmap.Lookup(keys[i]) < 0;
    cmap.SetMany(keys, c);
  };
  auto C = [&](int x, int y, int z) {
    if (!carving) return 0.0;
    const Key k = Pack(x, y, z);
    if (const double* known = cmap.Lookup(k)) return *known;
    G(x, y, z);
    eval_carve({k});
    return *cmap.Lookup(k);
  };
  // Both read (so every node in gmap is in cmap too).
  auto In = [&](int x, int y, int z) {
    const double g = G(x, y, z), c = C(x, y, z);
    return g < 0 && !(c > 0);
  };
  // The values a round of cells needs, computed in parallel before the round
  // (each block with its own memo: the same bits as the serial memo): first
  // the raw values at the cells' corners; then, for the island rule, the face
  // neighbours of the corners that could still be islands (a corner with a
  // known neighbour on its own side is not one, whatever the others are);
  // then the values marching cubes sees at the corners, inserted in key order.
  auto eval_raw = [&](std::vector<Key>& need) {
    SortUnique(need);
    std::vector<double> val(need.size());
    ParallelFor(static_cast<std::int64_t>(need.size()), [&](std::int64_t b0, std::int64_t e0) {
      Memo memo(lv_.size());
      for (std::int64_t i = b0; i < e0; ++i)
        val[i] = iso - ValueWith(Lmax_, Pack(KX(need[i]) << up, KY(need[i]) << up, KZ(need[i]) << up), memo);
    }, 512);
    rmap.SetMany(need, val);
  };
  static const int kFaceNb[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  // Keys fn(i, out) appends for i in [0, n) (callers sort them anyway).
  auto gather = [&](std::int64_t n, auto&& fn) { return GatherInBlocks<Key>(n, fn); };
  // Everything G needs at the nodes `cand` (any that are not in gmap yet).
  auto prefetch_nodes = [&](std::vector<Key> cand) {
    SortUnique(cand);
    std::vector<Key> gneed = gather(static_cast<std::int64_t>(cand.size()), [&](std::int64_t i, std::vector<Key>& out) {
      if (!gmap.Lookup(cand[i])) out.push_back(cand[i]);
    });
    std::vector<Key> need = gather(static_cast<std::int64_t>(gneed.size()), [&](std::int64_t i, std::vector<Key>& out) {
      if (!rmap.Lookup(gneed[i])) out.push_back(gneed[i]);
    });
    eval_raw(need);
    if (o_.remove_node_islands) {
      // Passes until every corner is settled: by a face neighbour outside
      // the grid or a known one on its own side (not an island), or by all
      // six known. Known neighbours are read first, whatever their place in
      // `seen`'s order: most corners are settled by a corner of their own
      // cells, with no node computed for them (session 40: the island
      // passes 1.04 -> 0.29 s, prefetches 3.1 -> 2.9 s in bunny_fixed
      // n = 40's 11 extractions). An unsettled corner asks for its first
      // unknown neighbour. A corner's value depends only on the values of
      // its neighbours, not on which other nodes were computed: the same
      // mesh.
      std::vector<Key> pending = gneed;
      while (!pending.empty()) {
        std::vector<Key> pairs = gather(static_cast<std::int64_t>(pending.size()), [&](std::int64_t i, std::vector<Key>& out) {
          const Key k = pending[i];
          const int x = KX(k), y = KY(k), z = KZ(k);
          const bool neg = *rmap.Lookup(k) < 0;
          Key first_unknown = 0;
          bool any_unknown = false;
          for (const auto& o : kFaceNb) {
            const int a = x + o[0], b = y + o[1], c = z + o[2];
            if (a < 0 || b < 0 || c < 0 || a > res || b > res || c > res) return;  // never an island
            const double* u = rmap.Lookup(Pack(a, b, c));
            if (!u) {
              if (!any_unknown) first_unknown = Pack(a, b, c);
              any_unknown = true;
              continue;
            }
            if ((*u < 0) == neg) return;  // not an island
          }
          if (any_unknown) {
            out.push_back(k);
            out.push_back(first_unknown);
          }
        });
        need.clear();
        pending.clear();
        for (std::size_t i = 0; i < pairs.size(); i += 2) {
          pending.push_back(pairs[i]);
          need.push_back(pairs[i + 1]);
        }
        eval_raw(need);
      }
    }
    std::vector<double> gv(gneed.size());
    std::vector<char> isl(gneed.size());
    // `seen`'s rule on what is known now: a corner with a neighbour outside
    // the grid or a known one on its own side is not an island; otherwise all
    // six are known and on the other side, and it takes their mean (summed
    // in `seen`'s order: the same bits).
    auto value_seen = [&](int x, int y, int z, bool* island) {
      const double v = *rmap.Lookup(Pack(x, y, z));
      *island = false;
      if (!o_.remove_node_islands) return v;
      double u[6];
      for (int j = 0; j < 6; ++j) {
        const int a = x + kFaceNb[j][0], b = y + kFaceNb[j][1], c = z + kFaceNb[j][2];
        if (a < 0 || b < 0 || c < 0 || a > res || b > res || c > res) return v;
        const double* known = rmap.Lookup(Pack(a, b, c));
        if (!known) return v;  // only a settled corner leaves a neighbour unknown
        u[j] = *known;
        if ((u[j] < 0) == (v < 0)) return v;
      }
      double mean = 0;
      for (int j = 0; j < 6; ++j) mean += u[j];
      *island = true;
      return mean / 6;
    };
    ParallelFor(static_cast<std::int64_t>(gneed.size()), [&](std::int64_t b0, std::int64_t e0) {
      for (std::int64_t i = b0; i < e0; ++i) {
        bool island;
        gv[i] = value_seen(KX(gneed[i]), KY(gneed[i]), KZ(gneed[i]), &island);
        isl[i] = island;
      }
    }, 1024);
    for (std::size_t i = 0; i < gneed.size(); ++i) islands_ += isl[i];
    gmap.SetMany(gneed, gv);
    eval_carve(gneed);
  };
  auto prefetch = [&](const std::vector<Key>& cells) {
    prefetch_nodes(gather(static_cast<std::int64_t>(cells.size()), [&](std::int64_t i, std::vector<Key>& out) {
      const int x = KX(cells[i]), y = KY(cells[i]), z = KZ(cells[i]);
      for (int q = 0; q < 8; ++q) {
        const Key k = Pack(x + (q & 1), y + ((q >> 1) & 1), z + ((q >> 2) & 1));
        if (!gmap.Lookup(k)) out.push_back(k);
      }
    }));
  };
  std::vector<Key> seeds;
  for (const Vec3& p : p_) {
    int c[3];
    double w[8];
    CellOf(p, res, c, w);
    seeds.push_back(Pack(c[0], c[1], c[2]));
  }
  // Sign changes on the complete level's edges, located on the finest grid.
  {
    const int rF = 1 << F_, step = 1 << (L - F_);
    {
      // The complete level's nodes, in parallel first (the search below reads
      // them): raw values, then the values marching cubes sees, by `seen`'s
      // rule. Their face neighbours (one extraction cell away, between the
      // lattice's nodes) are evaluated for the island test but not kept: kept,
      // each made a brick of its own in rmap, tens of thousands per
      // extraction, nearly all never read again. The values are the same.
      std::vector<Key> all;
      all.reserve(static_cast<std::size_t>(rF + 1) * (rF + 1) * (rF + 1));
      for (int z = 0; z <= rF; ++z)
        for (int y = 0; y <= rF; ++y)
          for (int x = 0; x <= rF; ++x) all.push_back(Pack(x * step, y * step, z * step));
      eval_raw(all);  // sorts `all`
      std::vector<double> gv(all.size());
      std::vector<char> isl(all.size(), 0);
      ParallelFor(static_cast<std::int64_t>(all.size()), [&](std::int64_t b0, std::int64_t e0) {
        Memo memo(lv_.size());
        auto raw = [&](int x, int y, int z) {
          if (const double* known = rmap.Lookup(Pack(x, y, z))) return *known;
          return iso - ValueWith(Lmax_, Pack(x << up, y << up, z << up), memo);
        };
        for (std::int64_t i = b0; i < e0; ++i) {
          bool island;
          gv[i] = seen(KX(all[i]), KY(all[i]), KZ(all[i]), raw, &island);
          isl[i] = island;
        }
      }, 512);
      for (std::size_t i = 0; i < all.size(); ++i) islands_ += isl[i];
      gmap.SetMany(all, gv);
      eval_carve(all);
    }
    for (int z = 0; z <= rF; ++z)
      for (int y = 0; y <= rF; ++y)
        for (int x = 0; x <= rF; ++x)
          for (int a = 0; a < 3; ++a) {
            int e[3] = {x, y, z};
            if (e[a] == rF) continue;
            int lo[3] = {x * step, y * step, z * step};
            int hi[3] = {lo[0], lo[1], lo[2]};
            hi[a] += step;
            const bool in0 = In(lo[0], lo[1], lo[2]), in1 = In(hi[0], hi[1], hi[2]);
            if (in0 == in1) continue;
            int l = lo[a], h = hi[a];
            while (h - l > 1) {
              const int m = (l + h) / 2;
              int q[3] = {lo[0], lo[1], lo[2]};
              q[a] = m;
              if (In(q[0], q[1], q[2]) == in0) l = m; else h = m;
            }
            int c[3] = {lo[0], lo[1], lo[2]};
            c[a] = l;
            for (int u = -1; u <= 0; ++u)
              for (int v = -1; v <= 0; ++v) {
                int cc[3] = {c[0], c[1], c[2]};
                cc[(a + 1) % 3] += u;
                cc[(a + 2) % 3] += v;
                if (cc[0] < 0 || cc[1] < 0 || cc[2] < 0 || cc[0] >= res || cc[1] >= res || cc[2] >= res) continue;
                seeds.push_back(Pack(cc[0], cc[1], cc[2]));
              }
          }
  }
  SortUnique(seeds);
  NodeCache<char> visited;
  for (Key s : seeds) visited.Set(s, 1);
  NodeCache<int> emap[3];
  std::vector<Vec3> verts;
  std::vector<std::array<int, 3>> tris;
  std::vector<char> on_chi;  // per vertex: placed at χ's crossing (not the carving field's)
  // The vertex on the edge from node (x, y, z) along `axis`, whose end
  // values are g0 and g1 (the edge's own G values) and c0, c1 (the carving
  // field; 0 without carving). Without carving: χ's crossing. With it, the
  // crossing nearer the edge's inside end of the two functions that change
  // side there (χ - iso at 0, c at 0), each linear along the edge.
  auto vertex = [&](int x, int y, int z, int axis, double g0, double g1, double c0, double c1) {
    const Key k = Pack(x, y, z);
    if (const int* id = emap[axis].Lookup(k)) return *id;
    double f = g0 / (g0 - g1);
    bool chi_vertex = true;  // placed at χ's crossing
    if (carving) {
      const bool in0 = g0 < 0 && !(c0 > 0);
      const bool g_cross = (g0 < 0) != (g1 < 0), c_cross = (c0 > 0) != (c1 > 0);
      if (c_cross) {
        int end[3] = {x, y, z};
        ++end[axis];
        // Beyond reach cmap may hold a bound only (never here for a
        // 1-Lipschitz c: one end claimed, both are within reach).
        const double v0 = std::abs(c0) < edge_len ? c0 : o_.carve.value(node_pos(k));
        const double v1 = std::abs(c1) < edge_len ? c1 : o_.carve.value(node_pos(Pack(end[0], end[1], end[2])));
        const double fc = std::clamp(v0 / (v0 - v1), 0.0, 1.0);
        if (!g_cross) {
          f = fc;
          chi_vertex = false;
        } else {
          chi_vertex = in0 ? f <= fc : f >= fc;
          f = in0 ? std::min(f, fc) : std::max(f, fc);
        }
      }
    }
    Vec3 pos((x + 0.0) / res, (y + 0.0) / res, (z + 0.0) / res);
    pos[axis] += f / res;
    emap[axis].Set(k, static_cast<int>(verts.size()));
    verts.push_back(pos);
    on_chi.push_back(chi_vertex);
    return static_cast<int>(verts.size()) - 1;
  };
  // Breadth-first, a round at a time: the cells of a round in the order a
  // first-in-first-out queue would give them, so the mesh is the same.
  std::vector<Key> round = std::move(seeds), next;
  std::vector<std::array<double, 8>> round_g, round_c;
  std::vector<int> round_config;
  prefetch(round);
  while (!round.empty()) {
    next.clear();
    // The corner values (all known after the prefetch) and configurations
    // of the round's cells, in parallel; then two serial passes in the
    // queue's order: one queues the neighbours (`visited`, `next`), the other
    // numbers vertices and makes triangles (`emap`, `verts`, `tris`). Neither
    // reads what the other writes, nor what the prefetch writes (`gmap`,
    // `rmap`, `islands_`), so the numbering runs beside the next round's
    // prefetch.
    round_g.resize(round.size());
    if (carving) round_c.resize(round.size());
    round_config.resize(round.size());
    ParallelFor(static_cast<std::int64_t>(round.size()), [&](std::int64_t b0, std::int64_t e0) {
      for (std::int64_t i = b0; i < e0; ++i) {
        const int x = KX(round[i]), y = KY(round[i]), z = KZ(round[i]);
        int config = 0;
        for (int q = 0; q < 8; ++q) {
          const Key k = Pack(x + (q & 1), y + ((q >> 1) & 1), z + ((q >> 2) & 1));
          const double v = *gmap.Lookup(k);
          round_g[i][q] = v;
          bool in = v < 0;
          if (carving) {
            const double c = *cmap.Lookup(k);
            round_c[i][q] = c;
            in = in && !(c > 0);
          }
          if (in) config |= 1 << q;
        }
        round_config[i] = config;
      }
    }, 512);
    // fn(x, y, z, corner values, carving values (null without), configuration)
    // for the round's cells that the surface crosses, in the queue's order.
    auto crossed = [&](auto&& fn) {
      for (std::size_t i = 0; i < round.size(); ++i) {
        const int config = round_config[i];
        if (config == 0 || config == 255) continue;
        fn(KX(round[i]), KY(round[i]), KZ(round[i]), round_g[i].data(), carving ? round_c[i].data() : nullptr,
           config);
      }
    };
    crossed([&](int x, int y, int z, const double*, const double*, int config) {
      // Faces with both signs lead to the neighbour across them.
      for (int a = 0; a < 3; ++a)
        for (int side = 0; side < 2; ++side) {
          bool any_in = false, any_out = false;
          for (int q = 0; q < 8; ++q) {
            if (((q >> a) & 1) != side) continue;
            (((config >> q) & 1) ? any_in : any_out) = true;
          }
          if (!(any_in && any_out)) continue;
          int nc[3] = {x, y, z};
          nc[a] += side ? 1 : -1;
          if (nc[a] < 0 || nc[a] >= res) continue;
          const Key nk = Pack(nc[0], nc[1], nc[2]);
          if (visited.Lookup(nk)) continue;
          visited.Set(nk, 1);
          next.push_back(nk);
        }
    });
    auto number = [&] {
      crossed([&](int x, int y, int z, const double* cg, const double* cc, int config) {
        for (const auto& tri : detail::MarchingCubesCase(config)) {
          std::array<int, 3> f;
          for (int k = 0; k < 3; ++k) {
            const int e = tri[k];
            const int c0 = detail::MarchingCubesEdgeCorner(e), axis = e / 4, c1 = c0 | (1 << axis);
            f[k] = vertex(x + (c0 & 1), y + ((c0 >> 1) & 1), z + ((c0 >> 2) & 1), axis, cg[c0], cg[c1],
                          cc ? cc[c0] : 0.0, cc ? cc[c1] : 0.0);
          }
          tris.push_back(f);
        }
      });
    };
    ParallelInvoke(number, [&] {
      if (!next.empty()) prefetch(next);
    });
    round.swap(next);
  }
  Mesh m;
  m.V.resize(static_cast<Eigen::Index>(verts.size()), 3);
  for (std::size_t i = 0; i < verts.size(); ++i)
    m.V.row(static_cast<Eigen::Index>(i)) = ((verts[i] - Vec3::Constant(0.5)) * side_ + center_).transpose();
  m.F.resize(static_cast<Eigen::Index>(tris.size()), 3);
  for (std::size_t i = 0; i < tris.size(); ++i)
    m.F.row(static_cast<Eigen::Index>(i)) << tris[i][0], tris[i][1], tris[i][2];
  if (carving && o_.carve_keep_voids == false) {
    // Carving cuts the surface χ proposes; a closed component with no vertex
    // on χ's surface is one it made alone: the boundary of a ball lying wholly
    // inside χ's solid (a void around an outside sample that the solid
    // covers). Such components are dropped: the surface keeps χ's components
    // and their cuts (session 42).
    int nc = 0;
    const std::vector<int> comp = FaceComponents(m, &nc);
    std::vector<char> has_chi(nc, 0);
    for (Eigen::Index f = 0; f < m.F.rows(); ++f)
      for (int k = 0; k < 3; ++k)
        if (on_chi[static_cast<std::size_t>(m.F(f, k))]) has_chi[comp[f]] = 1;
    long long dropped = 0;
    for (int c = 0; c < nc; ++c) dropped += !has_chi[c];
    if (dropped > 0) {
      std::vector<char> keep(static_cast<std::size_t>(m.F.rows()));
      for (Eigen::Index f = 0; f < m.F.rows(); ++f) keep[f] = has_chi[comp[f]];
      m = KeepFaces(m, keep);
      carve_only_ += dropped;
    }
  }
  return m;
}

}  // namespace arcs::spsr_detail
