#include "framework/rfta/free_space.h"

#include "framework/error.h"
#include "framework/rfta/sphere_tree.h"
#include "framework/util/parallel.h"
#include "framework/util/rng.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace arcs {
namespace {
inline double ToUnit01(std::uint64_t h) { return static_cast<double>(h >> 11) * 0x1.0p-53; }
}  // namespace

Vec3 RasterCellPoint(std::uint64_t seed, int res, int dim, bool jitter, std::int64_t i, std::int64_t j,
                     std::int64_t k) {
  if (!jitter) return Vec3((i + 0.5) / res, (j + 0.5) / res, dim == 3 ? (k + 0.5) / res : 0.0);
  const std::uint64_t cell =
      static_cast<std::uint64_t>(i) +
      static_cast<std::uint64_t>(res) * (static_cast<std::uint64_t>(j) +
                                         static_cast<std::uint64_t>(res) * static_cast<std::uint64_t>(k));
  std::uint64_t h = HashSeed(seed, cell);
  const double u0 = ToUnit01(h);
  h = SplitMix64(h);
  const double u1 = ToUnit01(h);
  if (dim == 2) return Vec3((i + u0) / res, (j + u1) / res, 0.0);
  h = SplitMix64(h);
  const double u2 = ToUnit01(h);
  return Vec3((i + u0) / res, (j + u1) / res, (k + u2) / res);
}

namespace {

inline double Sq(double v) { return v * v; }

// Pads the boxes of the conservative box tests so that rounding can never
// settle a box whose cell points the exact per-point test would decide
// otherwise (cell points lie in [i/res, (i+1)/res] up to rounding).
constexpr double kBoxPad = 1e-12;

// ---------------------------------------------------------------------------
// The raster grid restricted to a cell range, in bricks of 8^d cells.

constexpr int kB = 8;  // brick edge (cells); a brick row of 8 cells is one byte

struct Mask {
  std::uint8_t row[kB * kB];  // row (y + 8 z): bit x = cell (x, y, z) of the brick
};

enum : std::uint32_t { kFree = 0, kCovered = 1, kMixed0 = 2 };  // brick states; mixed = kMixed0 + mask

struct Grid {
  int dim = 3;
  int res = 0;
  std::int64_t lo[3] = {0, 0, 0}, hi[3] = {0, 0, 1};  // cell range [lo, hi) per axis
  std::int64_t nb[3] = {0, 0, 1};                     // bricks per axis
  int bs[3] = {kB, kB, kB};                           // brick edge per axis (z: 1 in 2D)
  std::uint64_t seed = 0;
  bool jitter = true;

  std::int64_t NumBricks() const { return nb[0] * nb[1] * nb[2]; }
  std::int64_t BrickIndex(std::int64_t bx, std::int64_t by, std::int64_t bz) const {
    return bx + nb[0] * (by + nb[1] * bz);
  }
  // Cell range of brick coordinate b along axis a.
  std::int64_t CellBegin(int a, std::int64_t b) const { return lo[a] + bs[a] * b; }
  std::int64_t CellEnd(int a, std::int64_t b) const { return std::min(lo[a] + bs[a] * (b + 1), hi[a]); }

  // The box [c0/res, c1/res] (padded) of the cells [c0, c1); z = 0 in 2D.
  void CellBox(const std::int64_t c0[3], const std::int64_t c1[3], Vec3* blo, Vec3* bhi) const {
    for (int a = 0; a < 3; ++a) {
      if (a == 2 && dim == 2) {
        (*blo)[a] = -kBoxPad;
        (*bhi)[a] = kBoxPad;
      } else {
        (*blo)[a] = static_cast<double>(c0[a]) / res - kBoxPad;
        (*bhi)[a] = static_cast<double>(c1[a]) / res + kBoxPad;
      }
    }
  }

  Vec3 CellPoint(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return RasterCellPoint(seed, res, dim, jitter, i, j, k);
  }
};

// Balls near one brick, copied out of the tree (squared effective radii).
struct LocalBall {
  double x, y, z, rr2;
};

// Per-thread scratch of the brick refinement.
struct BrickScratch {
  std::vector<int> found;
  std::vector<LocalBall> balls;
  std::vector<int> level[2];  // candidate lists of the sub-boxes of edge 4 and 2
};

// Sets the bits of cells [c0, c1) (absolute) in the mask of the brick at
// absolute cell origin o.
void SetBits(Mask* m, const std::int64_t o[3], const std::int64_t c0[3], const std::int64_t c1[3]) {
  const int x0 = static_cast<int>(c0[0] - o[0]), x1 = static_cast<int>(c1[0] - o[0]);
  const std::uint8_t bits = static_cast<std::uint8_t>(((1u << x1) - 1u) & ~((1u << x0) - 1u));
  for (std::int64_t z = c0[2]; z < c1[2]; ++z)
    for (std::int64_t y = c0[1]; y < c1[1]; ++y) m->row[(y - o[1]) + kB * (z - o[2])] |= bits;
}

// Refines the cells [c0, c1) of a brick (absolute cell coordinates; nominal
// edge `size`) against the balls `list` (indices into s->balls): a sub-box in
// one ball is set whole, a sub-box no ball reaches stays free, and boxes of
// edge <= 2 are tested point by point.
void Refine(const Grid& g, const std::int64_t o[3], const std::int64_t c0[3], const std::int64_t c1[3],
            int size, const std::vector<int>& list, int depth, BrickScratch* s, Mask* m) {
  const int half = size / 2;
  std::int64_t split[3];
  for (int a = 0; a < 3; ++a) split[a] = (a == 2 && g.dim == 2) ? c1[a] : std::min(c0[a] + half, c1[a]);
  std::vector<int>& sub = s->level[depth];
  for (int oz = 0; oz < 2; ++oz)
    for (int oy = 0; oy < 2; ++oy)
      for (int ox = 0; ox < 2; ++ox) {
        const int off[3] = {ox, oy, oz};
        std::int64_t b0[3], b1[3];
        bool empty = false;
        for (int a = 0; a < 3; ++a) {
          b0[a] = off[a] ? split[a] : c0[a];
          b1[a] = off[a] ? c1[a] : split[a];
          empty = empty || b0[a] >= b1[a];
        }
        if (empty) continue;
        Vec3 blo, bhi;
        g.CellBox(b0, b1, &blo, &bhi);
        const Vec3 mid = 0.5 * (blo + bhi), hw = 0.5 * (bhi - blo);
        sub.clear();
        bool covered = false;
        for (int t : list) {
          const LocalBall& b = s->balls[t];
          const double c[3] = {b.x, b.y, b.z};
          double near = 0.0, far = 0.0;
          for (int a = 0; a < 3; ++a) {
            const double d = std::abs(c[a] - mid[a]);
            near += Sq(std::max(0.0, d - hw[a]));
            far += Sq(d + hw[a]);
          }
          if (near > b.rr2) continue;
          if (far <= b.rr2) {
            covered = true;
            break;
          }
          sub.push_back(t);
        }
        if (covered) {
          SetBits(m, o, b0, b1);
          continue;
        }
        if (sub.empty()) continue;
        if (half > 2) {
          // Deeper levels write s->level[depth + 1] only, so `sub` stays valid.
          Refine(g, o, b0, b1, half, sub, depth + 1, s, m);
          continue;
        }
        // Edge <= 2: the exact per-point rule (official: |x - c|^2 <= 0.95 r^2).
        for (std::int64_t k = b0[2]; k < b1[2]; ++k)
          for (std::int64_t j = b0[1]; j < b1[1]; ++j)
            for (std::int64_t i = b0[0]; i < b1[0]; ++i) {
              const Vec3 p = g.CellPoint(i, j, k);
              for (int t : sub) {
                const LocalBall& b = s->balls[t];
                if (Sq(p.x() - b.x) + Sq(p.y() - b.y) + Sq(p.z() - b.z) <= b.rr2) {
                  m->row[(j - o[1]) + kB * (k - o[2])] |= static_cast<std::uint8_t>(1u << (i - o[0]));
                  break;
                }
              }
            }
      }
}

// Classifies one brick: kFree, kCovered, or kMixed0 with *m filled.
std::uint32_t ProcessBrick(const Grid& g, const SphereTree& tree, double shrink, std::int64_t bx,
                           std::int64_t by, std::int64_t bz, BrickScratch* s, Mask* m) {
  const std::int64_t b[3] = {bx, by, bz};
  std::int64_t c0[3], c1[3];
  for (int a = 0; a < 3; ++a) {
    c0[a] = g.CellBegin(a, b[a]);
    c1[a] = g.CellEnd(a, b[a]);
  }
  Vec3 blo, bhi;
  g.CellBox(c0, c1, &blo, &bhi);
  if (tree.AnyCoversBox(blo, bhi, shrink)) return kCovered;
  s->found.clear();
  tree.CollectIntersectingBox(blo, bhi, shrink, &s->found);
  if (s->found.empty()) return kFree;
  s->balls.resize(s->found.size());
  std::vector<int> all(s->found.size());
  for (std::size_t t = 0; t < s->found.size(); ++t) {
    const SphereTree::Ball& ball = tree.ball(s->found[t]);
    s->balls[t] = {ball.x, ball.y, ball.z, shrink * ball.r * ball.r};
    all[t] = static_cast<int>(t);
  }
  std::fill(std::begin(m->row), std::end(m->row), 0);
  Refine(g, c0, c0, c1, kB, all, 0, s, m);
  // Free / covered / mixed over the in-range cells.
  const int nx = static_cast<int>(c1[0] - c0[0]);
  const std::uint8_t full = static_cast<std::uint8_t>((1u << nx) - 1u);
  bool any = false, all_set = true;
  for (std::int64_t z = 0; z < c1[2] - c0[2]; ++z)
    for (std::int64_t y = 0; y < c1[1] - c0[1]; ++y) {
      const std::uint8_t r = m->row[y + kB * z];
      any = any || r != 0;
      all_set = all_set && r == full;
    }
  if (!any) return kFree;
  if (all_set) return kCovered;
  return kMixed0;
}

}  // namespace

void RasterizeOptions::Check() const {
  ARCS_CHECK_OPTION(resolution == 0 || (resolution >= 2 && resolution <= 2048), "resolution", resolution,
                    "0 (heuristic) or in [2, 2048]");
  ARCS_CHECK_OPTION(max_resolution >= 2 && max_resolution <= 2048, "max_resolution", max_resolution,
                    "in [2, 2048]");
  ARCS_CHECK_OPTION(shrink > 0.0 && shrink <= 1.0, "shrink", shrink, "in (0, 1]");
}

int RasterResolution(const RasterizeOptions& o, std::int64_t num_samples, int dim) {
  return o.resolution > 0 ? o.resolution : RasterResolutionHeuristic(num_samples, dim, o.max_resolution);
}

MatrixX3d RasterizeNarrowBand(const SphereSet& spheres, int resolution, const RasterizeOptions& o,
                              std::uint64_t seed, RasterizeStats* stats) {
  o.Check();
  if (resolution < 2 || resolution > 2048)
    throw OptionError("resolution = " + std::to_string(resolution) + ": must be in [2, 2048]");
  RasterizeStats st;
  st.resolution = resolution;
  MatrixX3d out(0, 3);
  if (spheres.Size() == 0) {
    if (stats) *stats = st;
    return out;
  }
  Grid g;
  g.dim = spheres.dim;
  g.res = resolution;
  g.seed = seed;
  g.jitter = o.jitter;
  if (g.dim == 2) g.bs[2] = 1;
  // Restricted grid: the spheres' bounding box +- 1 cell (official).
  for (int a = 0; a < g.dim; ++a) {
    const double bmin = (spheres.centers.col(a) - spheres.radii).minCoeff();
    const double bmax = (spheres.centers.col(a) + spheres.radii).maxCoeff();
    const double l = std::floor(bmin * resolution) - 1.0, h = std::floor(bmax * resolution) + 2.0;
    g.lo[a] = static_cast<std::int64_t>(std::clamp(l, 0.0, static_cast<double>(resolution)));
    g.hi[a] = static_cast<std::int64_t>(std::clamp(h, 0.0, static_cast<double>(resolution)));
  }
  for (int a = 0; a < 3; ++a) {
    if (g.hi[a] <= g.lo[a]) {
      if (stats) *stats = st;
      return out;
    }
    g.nb[a] = (g.hi[a] - g.lo[a] + g.bs[a] - 1) / g.bs[a];
  }
  st.range_cells = (g.hi[0] - g.lo[0]) * (g.hi[1] - g.lo[1]) * (g.hi[2] - g.lo[2]);

  const SphereTree tree(spheres.centers, spheres.radii, spheres.sample);
  const double shrink = o.shrink;

  // 1. Octree over bricks, level by level: a node inside one ball is covered,
  //    a node no ball reaches is free, others split; single bricks are
  //    refined in step 2.
  std::vector<std::uint32_t> state(g.NumBricks(), kFree);
  struct Node {
    std::int64_t b0[3];
    std::int64_t size;
  };
  std::int64_t root = 1;
  while (root < std::max({g.nb[0], g.nb[1], g.nb[2]})) root *= 2;
  std::vector<Node> level = {Node{{0, 0, 0}, root}};
  std::vector<std::int64_t> bricks;  // brick indices to refine
  while (!level.empty()) {
    std::vector<std::uint8_t> kind(level.size());  // 0 free, 1 covered, 2 split, 3 brick
    ParallelFor(
        static_cast<std::int64_t>(level.size()),
        [&](std::int64_t begin, std::int64_t end) {
          for (std::int64_t n = begin; n < end; ++n) {
            const Node& nd = level[n];
            if (nd.size == 1) {
              kind[n] = 3;
              continue;
            }
            std::int64_t c0[3], c1[3];
            for (int a = 0; a < 3; ++a) {
              c0[a] = g.CellBegin(a, nd.b0[a]);
              c1[a] = g.CellEnd(a, std::min(nd.b0[a] + nd.size, g.nb[a]) - 1);
            }
            Vec3 blo, bhi;
            g.CellBox(c0, c1, &blo, &bhi);
            if (tree.AnyCoversBox(blo, bhi, shrink)) kind[n] = 1;
            else if (!tree.AnyIntersectsBox(blo, bhi, shrink)) kind[n] = 0;
            else kind[n] = 2;
          }
        },
        1);
    std::vector<Node> next;
    for (std::size_t n = 0; n < level.size(); ++n) {
      const Node& nd = level[n];
      if (kind[n] == 3) {
        bricks.push_back(g.BrickIndex(nd.b0[0], nd.b0[1], nd.b0[2]));
      } else if (kind[n] == 1) {
        for (std::int64_t z = nd.b0[2]; z < std::min(nd.b0[2] + nd.size, g.nb[2]); ++z)
          for (std::int64_t y = nd.b0[1]; y < std::min(nd.b0[1] + nd.size, g.nb[1]); ++y)
            for (std::int64_t x = nd.b0[0]; x < std::min(nd.b0[0] + nd.size, g.nb[0]); ++x)
              state[g.BrickIndex(x, y, z)] = kCovered;
      } else if (kind[n] == 2) {
        const std::int64_t h = nd.size / 2;
        for (int oz = 0; oz < 2; ++oz)
          for (int oy = 0; oy < 2; ++oy)
            for (int ox = 0; ox < 2; ++ox) {
              const Node c{{nd.b0[0] + ox * h, nd.b0[1] + oy * h, nd.b0[2] + oz * h}, h};
              if (c.b0[0] < g.nb[0] && c.b0[1] < g.nb[1] && c.b0[2] < g.nb[2]) next.push_back(c);
            }
      }
    }
    level.swap(next);
  }
  std::sort(bricks.begin(), bricks.end());
  st.surface_bricks = static_cast<std::int64_t>(bricks.size());

  // 2. Bricks near the boundary, cell by cell.
  std::vector<Mask> brick_mask(bricks.size());
  std::vector<std::uint32_t> brick_kind(bricks.size());
  ParallelFor(
      static_cast<std::int64_t>(bricks.size()),
      [&](std::int64_t begin, std::int64_t end) {
        BrickScratch s;
        for (std::int64_t t = begin; t < end; ++t) {
          const std::int64_t bi = bricks[t];
          const std::int64_t bx = bi % g.nb[0], by = (bi / g.nb[0]) % g.nb[1], bz = bi / (g.nb[0] * g.nb[1]);
          brick_kind[t] = ProcessBrick(g, tree, shrink, bx, by, bz, &s, &brick_mask[t]);
        }
      },
      4);
  std::vector<Mask> masks;
  for (std::size_t t = 0; t < bricks.size(); ++t) {
    if (brick_kind[t] == kMixed0) {
      state[bricks[t]] = kMixed0 + static_cast<std::uint32_t>(masks.size());
      masks.push_back(brick_mask[t]);
    } else {
      state[bricks[t]] = brick_kind[t];
    }
  }
  st.mixed_bricks = static_cast<std::int64_t>(masks.size());
  const std::size_t refine_bytes = brick_mask.capacity() * sizeof(Mask) + bricks.capacity() * 8;
  std::vector<Mask>().swap(brick_mask);

  // Occupancy row (8 bits along x) of brick (bx, by, bz), row (y, z) of it;
  // 0 outside the brick grid or the cell range.
  auto row_bits = [&](std::int64_t bx, std::int64_t by, std::int64_t bz, int y, int z) -> std::uint32_t {
    if (bx < 0 || by < 0 || bz < 0 || bx >= g.nb[0] || by >= g.nb[1] || bz >= g.nb[2]) return 0;
    const std::uint32_t sv = state[g.BrickIndex(bx, by, bz)];
    if (sv == kFree) return 0;
    if (sv >= kMixed0) return masks[sv - kMixed0].row[y + kB * z];
    if (g.CellBegin(1, by) + y >= g.hi[1] || g.CellBegin(2, bz) + z >= g.hi[2]) return 0;
    const std::int64_t nx = g.CellEnd(0, bx) - g.CellBegin(0, bx);
    return (1u << nx) - 1u;
  };

  // 3. Candidate bricks for the band: mixed ones, and free ones next to a
  //    brick with occupied cells.
  const int zr = g.dim == 3 ? 1 : 0;
  std::vector<std::uint8_t> candidate(g.NumBricks(), 0);
  ParallelFor(
      g.NumBricks(),
      [&](std::int64_t begin, std::int64_t end) {
        for (std::int64_t bi = begin; bi < end; ++bi) {
          const std::uint32_t sv = state[bi];
          if (sv == kCovered) continue;
          if (sv >= kMixed0) {
            candidate[bi] = 1;
            continue;
          }
          const std::int64_t bx = bi % g.nb[0], by = (bi / g.nb[0]) % g.nb[1], bz = bi / (g.nb[0] * g.nb[1]);
          bool near = false;
          for (int dz = -zr; dz <= zr && !near; ++dz)
            for (int dy = -1; dy <= 1 && !near; ++dy)
              for (int dx = -1; dx <= 1 && !near; ++dx) {
                const std::int64_t x = bx + dx, y = by + dy, z = bz + dz;
                if (x < 0 || y < 0 || z < 0 || x >= g.nb[0] || y >= g.nb[1] || z >= g.nb[2]) continue;
                near = state[g.BrickIndex(x, y, z)] != kFree;
              }
          candidate[bi] = near ? 1 : 0;
        }
      },
      4096);
  std::vector<std::int64_t> cand;
  for (std::int64_t bi = 0; bi < g.NumBricks(); ++bi)
    if (candidate[bi]) cand.push_back(bi);
  std::vector<std::uint8_t>().swap(candidate);

  // 4. Band of each candidate: free cells with an occupied 3^d neighbour, by
  //    bit dilation of a padded 10 x 10 x 10 occupancy block.
  std::vector<Mask> band(cand.size());
  std::vector<std::int64_t> count(cand.size() + 1, 0);
  const int bz_cells = g.bs[2];
  ParallelFor(
      static_cast<std::int64_t>(cand.size()),
      [&](std::int64_t begin, std::int64_t end) {
        for (std::int64_t t = begin; t < end; ++t) {
          const std::int64_t bi = cand[t];
          const std::int64_t bx = bi % g.nb[0], by = (bi / g.nb[0]) % g.nb[1], bz = bi / (g.nb[0] * g.nb[1]);
          // Padded rows: P[z + 1][y + 1], bit x + 1 for x in [-1, 8].
          std::uint32_t P[kB + 2][kB + 2];
          for (int z = -1; z <= bz_cells; ++z)
            for (int y = -1; y <= kB; ++y) {
              std::uint32_t r = 0;
              const bool zin = g.dim == 3 || z == 0;
              if (zin) {
                const std::int64_t nby = by + (y < 0 ? -1 : (y >= kB ? 1 : 0));
                const std::int64_t nbz = g.dim == 3 ? bz + (z < 0 ? -1 : (z >= kB ? 1 : 0)) : 0;
                const int yy = (y + kB) % kB, zz = g.dim == 3 ? (z + kB) % kB : 0;
                r = row_bits(bx, nby, nbz, yy, zz) << 1;
                r |= (row_bits(bx - 1, nby, nbz, yy, zz) >> 7) & 1u;
                r |= (row_bits(bx + 1, nby, nbz, yy, zz) & 1u) << 9;
              }
              P[z + 1][y + 1] = r;
            }
          // Dilate along x, then y and z.
          std::uint32_t H[kB + 2][kB + 2];
          for (int z = 0; z < bz_cells + 2; ++z)
            for (int y = 0; y < kB + 2; ++y) {
              const std::uint32_t r = P[z][y];
              H[z][y] = r | (r << 1) | (r >> 1);
            }
          Mask& bm = band[t];
          std::int64_t c = 0;
          const std::int64_t x0 = g.CellBegin(0, bx), y0 = g.CellBegin(1, by), z0 = g.CellBegin(2, bz);
          const std::uint32_t inx = (1u << (g.CellEnd(0, bx) - x0)) - 1u;
          for (int z = 0; z < kB; ++z)
            for (int y = 0; y < kB; ++y) {
              std::uint8_t out_row = 0;
              if (z < bz_cells && y0 + y < g.hi[1] && z0 + z < g.hi[2]) {
                std::uint32_t d = 0;
                for (int dz = (g.dim == 3 ? 0 : 1); dz <= (g.dim == 3 ? 2 : 1); ++dz)
                  for (int dy = 0; dy <= 2; ++dy) d |= H[z + dz][y + dy];
                const std::uint32_t occ = P[z + 1][y + 1];
                out_row = static_cast<std::uint8_t>(((d & ~occ) >> 1) & inx);
              }
              bm.row[y + kB * z] = out_row;
              c += std::popcount(static_cast<unsigned>(out_row));
            }
          count[t + 1] = c;
        }
      },
      64);
  for (std::size_t t = 0; t < cand.size(); ++t) count[t + 1] += count[t];
  const std::int64_t total = count[cand.size()];
  out.resize(total, 3);
  ParallelFor(
      static_cast<std::int64_t>(cand.size()),
      [&](std::int64_t begin, std::int64_t end) {
        for (std::int64_t t = begin; t < end; ++t) {
          const std::int64_t bi = cand[t];
          const std::int64_t bx = bi % g.nb[0], by = (bi / g.nb[0]) % g.nb[1], bz = bi / (g.nb[0] * g.nb[1]);
          const std::int64_t x0 = g.CellBegin(0, bx), y0 = g.CellBegin(1, by), z0 = g.CellBegin(2, bz);
          std::int64_t w = count[t];
          for (int z = 0; z < kB; ++z)
            for (int y = 0; y < kB; ++y) {
              const std::uint8_t r = band[t].row[y + kB * z];
              for (int x = 0; x < kB; ++x)
                if (r >> x & 1u) out.row(w++) = g.CellPoint(x0 + x, y0 + y, z0 + z).transpose();
            }
        }
      },
      64);
  st.band_points = total;
  st.memory_bytes = tree.MemoryBytes() + state.capacity() * sizeof(std::uint32_t) +
                    masks.capacity() * sizeof(Mask) + refine_bytes +
                    band.capacity() * sizeof(Mask) + cand.capacity() * 16 +
                    static_cast<std::size_t>(total) * 3 * sizeof(double) +
                    static_cast<std::size_t>(g.NumBricks());
  if (stats) *stats = st;
  return out;
}

FreeSpaceSamples RasterizeFreeSpace(const SdfSamples& samples, const RasterizeOptions& o, const Context& ctx,
                                    RasterizeStats stats[2]) {
  o.Check();
  CheckRftaSamples(samples, "rasterize");
  const SignedSpheres sp = SplitSpheresBySign(samples, SignSplitOptions());
  RequireBothSigns(sp, "rasterize");
  const int res = RasterResolution(o, sp.num_samples, samples.dim);
  RasterizeStats st[2];
  const MatrixX3d pos = RasterizeNarrowBand(sp.positive, res, o, ctx.StreamSeed("rasterize/positive"), &st[0]);
  ctx.CheckStop();
  const MatrixX3d neg = RasterizeNarrowBand(sp.negative, res, o, ctx.StreamSeed("rasterize/negative"), &st[1]);
  if (stats) {
    stats[0] = st[0];
    stats[1] = st[1];
  }
  return MergeFreeSpace(sp.frame, pos, neg);
}

// ---------------------------------------------------------------------------
// Rejection sampling.

void RejectionOptions::Check() const {
  ARCS_CHECK_OPTION(count >= 1 && count <= 1000000000, "count", count, "in [1, 1e9]");
  ARCS_CHECK_OPTION(shrink > 0.0 && shrink <= 1.0, "shrink", shrink, "in (0, 1]");
  ARCS_CHECK_OPTION(max_draws >= count, "max_draws", max_draws, ">= count");
}

namespace {

Vec3 UniformPoint(std::uint64_t seed, std::uint64_t index, int dim) {
  std::uint64_t h = HashSeed(seed, index);
  const double u0 = ToUnit01(h);
  h = SplitMix64(h);
  const double u1 = ToUnit01(h);
  if (dim == 2) return Vec3(u0, u1, 0.0);
  h = SplitMix64(h);
  return Vec3(u0, u1, ToUnit01(h));
}

}  // namespace

MatrixX3d RejectionSampleFreeSpace(const SphereSet& spheres, const RejectionOptions& o, std::uint64_t seed,
                                   std::int64_t* draws) {
  o.Check();
  const SphereTree tree(spheres.centers, spheres.radii, spheres.sample);
  std::vector<Vec3> kept;
  std::int64_t used = 0;
  const std::int64_t round = std::max<std::int64_t>(1 << 15, std::min<std::int64_t>(o.count, 1 << 22));
  std::vector<std::uint8_t> free(round);
  while (static_cast<std::int64_t>(kept.size()) < o.count && used < o.max_draws) {
    const std::int64_t n = std::min(round, o.max_draws - used);
    ParallelFor(
        n,
        [&](std::int64_t begin, std::int64_t end) {
          for (std::int64_t t = begin; t < end; ++t)
            free[t] = !tree.AnyCovers(UniformPoint(seed, used + t, spheres.dim), o.shrink);
        },
        1024);
    // Keep in draw order, so the first `count` free draws are the result.
    std::int64_t t = 0;
    for (; t < n && static_cast<std::int64_t>(kept.size()) < o.count; ++t)
      if (free[t]) kept.push_back(UniformPoint(seed, used + t, spheres.dim));
    used += t;
  }
  if (draws) *draws = used;
  MatrixX3d out(kept.size(), 3);
  for (std::size_t i = 0; i < kept.size(); ++i) out.row(i) = kept[i].transpose();
  return out;
}

FreeSpaceSamples RejectionFreeSpace(const SdfSamples& samples, const RejectionOptions& o, const Context& ctx) {
  o.Check();
  CheckRftaSamples(samples, "rejection");
  const SignedSpheres sp = SplitSpheresBySign(samples, SignSplitOptions());
  RequireBothSigns(sp, "rejection");
  MatrixX3d pts[2];
  for (int s = 0; s < 2; ++s) {
    std::int64_t draws = 0;
    pts[s] = RejectionSampleFreeSpace(s == 0 ? sp.positive : sp.negative, o,
                                      ctx.StreamSeed(s == 0 ? "rejection/positive" : "rejection/negative"), &draws);
    if (pts[s].rows() < o.count) {
      ctx.Warn(std::string("rejection: only ") + std::to_string(pts[s].rows()) + " of " +
               std::to_string(o.count) + (s == 0 ? " positive" : " negative") + " free points after " +
               std::to_string(draws) + " draws (max_draws)");
    }
    ctx.CheckStop();
  }
  return MergeFreeSpace(sp.frame, pts[0], pts[1]);
}

// ---------------------------------------------------------------------------
// Metropolis–Hastings.

void MetropolisOptions::Check() const {
  ARCS_CHECK_OPTION(count >= 1 && count <= 1000000000, "count", count, "in [1, 1e9]");
  ARCS_CHECK_OPTION(shrink > 0.0 && shrink <= 1.0, "shrink", shrink, "in (0, 1]");
  ARCS_CHECK_OPTION(sigma >= 0.0 && sigma <= 1.0, "sigma", sigma, "in [0, 1] (0 = a quarter sample spacing)");
  ARCS_CHECK_OPTION(step >= 0.0 && step <= 1.0, "step", step, "in [0, 1] (0 = sigma)");
  ARCS_CHECK_OPTION(chains >= 1 && chains <= 1 << 20, "chains", chains, "in [1, 2^20]");
  ARCS_CHECK_OPTION(burn_in >= 0, "burn_in", burn_in, ">= 0");
  ARCS_CHECK_OPTION(max_steps >= 0, "max_steps", max_steps, ">= 0 (0 = automatic)");
}

MatrixX3d MetropolisSampleFreeSpace(const SphereSet& spheres, std::int64_t num_samples, const MetropolisOptions& o,
                                    std::uint64_t seed) {
  o.Check();
  const SphereTree tree(spheres.centers, spheres.radii, spheres.sample);
  const int dim = spheres.dim;
  const double sigma = o.sigma > 0.0 ? o.sigma : 0.25 / SamplesPerAxis(std::max<std::int64_t>(num_samples, 1), dim);
  const double step = o.step > 0.0 ? o.step : sigma;
  const double scale = std::sqrt(o.shrink);
  const std::int64_t per_chain = (o.count + o.chains - 1) / o.chains;
  const std::int64_t max_steps = o.max_steps > 0 ? o.max_steps : o.burn_in + 50 * per_chain;
  std::vector<std::vector<Vec3>> chain_out(o.chains);
  ParallelFor(
      o.chains,
      [&](std::int64_t begin, std::int64_t end) {
        for (std::int64_t c = begin; c < end; ++c) {
          Rng rng(HashSeed(seed, static_cast<std::uint64_t>(c)));
          auto uniform = [&]() {
            const double x = rng.Uniform(), y = rng.Uniform();
            return Vec3(x, y, dim == 3 ? rng.Uniform() : 0.0);
          };
          // Start: a uniform free point (the chain is dropped if none is found).
          Vec3 x;
          bool started = false;
          for (int t = 0; t < 100000 && !started; ++t) {
            x = uniform();
            started = !tree.AnyCovers(x, o.shrink);
          }
          if (!started) continue;
          double dx = std::max(0.0, tree.DistanceToUnion(x, scale));
          std::vector<Vec3>& out = chain_out[c];
          for (std::int64_t s = 0; s < max_steps && static_cast<std::int64_t>(out.size()) < per_chain; ++s) {
            Vec3 y = x + step * Vec3(rng.Normal(), rng.Normal(), dim == 3 ? rng.Normal() : 0.0);
            const double u = rng.Uniform();
            if ((y.array() < 0.0).any() || (y.array() > 1.0).any()) continue;
            if (tree.AnyCovers(y, o.shrink)) continue;
            const double dy = std::max(0.0, tree.DistanceToUnion(y, scale));
            if (u >= std::exp(-(dy - dx) / sigma)) continue;
            x = y;
            dx = dy;
            if (s >= o.burn_in) out.push_back(x);
          }
        }
      },
      1);
  std::int64_t total = 0;
  for (const auto& v : chain_out) total += static_cast<std::int64_t>(v.size());
  total = std::min(total, o.count);
  MatrixX3d out(total, 3);
  std::int64_t w = 0;
  for (const auto& v : chain_out)
    for (const Vec3& p : v) {
      if (w == total) break;
      out.row(w++) = p.transpose();
    }
  return out;
}

FreeSpaceSamples MetropolisFreeSpace(const SdfSamples& samples, const MetropolisOptions& o, const Context& ctx) {
  o.Check();
  CheckRftaSamples(samples, "metropolis_hastings");
  const SignedSpheres sp = SplitSpheresBySign(samples, SignSplitOptions());
  RequireBothSigns(sp, "metropolis_hastings");
  MatrixX3d pts[2];
  for (int s = 0; s < 2; ++s) {
    pts[s] = MetropolisSampleFreeSpace(s == 0 ? sp.positive : sp.negative, sp.num_samples, o,
                                       ctx.StreamSeed(s == 0 ? "metropolis/positive" : "metropolis/negative"));
    if (pts[s].rows() < o.count) {
      ctx.Warn(std::string("metropolis_hastings: only ") + std::to_string(pts[s].rows()) + " of " +
               std::to_string(o.count) + (s == 0 ? " positive" : " negative") + " free points (max_steps)");
    }
    ctx.CheckStop();
  }
  return MergeFreeSpace(sp.frame, pts[0], pts[1]);
}

}  // namespace arcs
