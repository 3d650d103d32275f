// The finite elements of arcs' screened Poisson (spsr.cpp): degree-1 tents
// on a level's grid cut at the unit cube's faces (Neumann), their 1D
// integrals and 27-point stencils, a point's cell and trilinear weights, the
// prolongation between levels, and the complete coarse grids of the base
// level's multigrid with their restriction and prolongation. Internal to
// framework/reconstruct, as spsr_keys.h: the solver and its tests use it.
#pragma once

#include "framework/types.h"
#include "framework/util/parallel.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace arcs::spsr_fem {

// 1D integrals of degree-1 tents on the level's grid (nodes 0..res, h = 1/res),
// cut at the cube's faces (Neumann): mass M, stiffness S (∫B_a' B_b'),
// derivative-value D (∫B_a' B_b), for b = a + o, o in {-1, 0, 1}.
struct Tent1D {
  double h;
  int res;
  double M(int a, int o) const {
    if (o != 0) return h / 6.0;
    return (a == 0 || a == res) ? h / 3.0 : 2.0 * h / 3.0;
  }
  double S(int a, int o) const {
    if (o != 0) return -1.0 / h;
    return (a == 0 || a == res) ? 1.0 / h : 2.0 / h;
  }
  double D(int a, int o) const {
    if (o == 1) return -0.5;
    if (o == -1) return 0.5;
    if (a == 0) return -0.5;
    if (a == res) return 0.5;
    return 0.0;
  }
};

// Offset o (0..26) -> (dx, dy, dz) in {-1,0,1}, x fastest.
inline int Ox(int o) { return o % 3 - 1; }
inline int Oy(int o) { return (o / 3) % 3 - 1; }
inline int Oz(int o) { return o / 9 - 1; }

// The tents' 1D factors depend on a node only through its class on each
// axis: 0 on the low face, 1 inside, 2 on the high face (res >= 2).
inline int AxisClass(int a, int res) { return a == 0 ? 0 : a == res ? 2 : 1; }
// The node's row of StencilByClass: cx + 3 cy + 9 cz.
inline int NodeClass(int x, int y, int z, int res) { return AxisClass(x, res) + 3 * AxisClass(y, res) + 9 * AxisClass(z, res); }
struct TentByClass {
  double M[3][3], S[3][3], D[3][3];  // [class][offset + 1]
  explicit TentByClass(const Tent1D& t) {
    const int at[3] = {0, t.res / 2, t.res};
    for (int c = 0; c < 3; ++c)
      for (int o = -1; o <= 1; ++o) {
        M[c][o + 1] = t.M(at[c], o);
        S[c][o + 1] = t.S(at[c], o);
        D[c][o + 1] = t.D(at[c], o);
      }
  }
};
// The stiffness stencil of a node of class cx + 3 cy + 9 cz, offset o
// (the same expression, so the same values, as from the tents directly).
using ClassStencil = std::array<std::array<double, 27>, 27>;
inline ClassStencil StencilByClass(const Tent1D& t) {
  const TentByClass b(t);
  ClassStencil k{};
  for (int c = 0; c < 27; ++c) {
    const int cx = c % 3, cy = (c / 3) % 3, cz = c / 9;
    for (int o = 0; o < 27; ++o) {
      const int ox = Ox(o) + 1, oy = Oy(o) + 1, oz = Oz(o) + 1;
      k[c][o] = b.S[cx][ox] * b.M[cy][oy] * b.M[cz][oz] + b.M[cx][ox] * b.S[cy][oy] * b.M[cz][oz] +
                b.M[cx][ox] * b.M[cy][oy] * b.S[cz][oz];
    }
  }
  return k;
}

// The cell (at `res` cells per side) containing unit-cube point p and the
// trilinear weights of its 8 corners (corner c: offset (c&1, c>>1&1, c>>2&1)).
inline void CellOf(const Vec3& p, int res, int c[3], double w[8]) {
  double t[3];
  for (int a = 0; a < 3; ++a) {
    const double u = p[a] * res;
    int i = static_cast<int>(std::floor(u));
    i = std::clamp(i, 0, res - 1);
    c[a] = i;
    t[a] = std::clamp(u - i, 0.0, 1.0);
  }
  for (int k = 0; k < 8; ++k) {
    w[k] = ((k & 1) ? t[0] : 1 - t[0]) * ((k & 2) ? t[1] : 1 - t[1]) * ((k & 4) ? t[2] : 1 - t[2]);
  }
}

// 1D prolongation of coarse level values to fine node coordinate a: coarse
// nodes and weights (1 node if a is even, 2 halves if odd).
inline int Parents1D(int a, int pc[2], double pw[2]) {
  if ((a & 1) == 0) {
    pc[0] = a >> 1;
    pw[0] = 1.0;
    return 1;
  }
  pc[0] = a >> 1;
  pc[1] = (a >> 1) + 1;
  pw[0] = pw[1] = 0.5;
  return 2;
}

// Σ w · at(cx, cy, cz) over the coarse parents of fine node (x, y, z) (the
// trilinear prolongation weights of Parents1D), z outermost, x innermost.
template <class T, class Fn>
T ParentSum(int x, int y, int z, Fn&& at) {
  int cx[2], cy[2], cz[2];
  double wx[2], wy[2], wz[2];
  const int nx = Parents1D(x, cx, wx), ny = Parents1D(y, cy, wy), nz = Parents1D(z, cz, wz);
  T v{};
  for (int c = 0; c < nz; ++c)
    for (int b = 0; b < ny; ++b)
      for (int a = 0; a < nx; ++a) v += wx[a] * wy[b] * wz[c] * at(cx[a], cy[b], cz[c]);
  return v;
}

// The z-slices per parallel task for the complete grids' loops, given the
// work of one slice: tasks of at least ~16k operations.
inline std::int64_t SliceGrain(std::int64_t per_slice) { return std::max<std::int64_t>(1, 16384 / per_slice); }

// A complete grid of level c (nodes (2^c + 1)^3, x fastest) for the base
// level's multigrid: its operator is the Galerkin one, P^T A P of the level
// above, which for nested tents is the same FEM assembled at this level (the
// stiffness of its own tents, the screening of the base level's samples
// weighted by its own trilinear weights and the base level's beta), stored
// as 27 coefficients per node.
struct CoarseGrid {
  int res = 0;
  std::vector<double> coef;  // 27 per node
  int N() const { return (res + 1) * (res + 1) * (res + 1); }
  int Idx(int x, int y, int z) const { return x + (res + 1) * (y + (res + 1) * z); }
  // The screening points: pts[idx[s]] for each s (idx null: every pts[s]),
  // weighted by count[s] (null: 1 each).
  void Build(int level, const std::vector<Vec3>& pts, const std::vector<int>* idx, const std::vector<double>* count,
             double beta) {
    res = 1 << level;
    const Tent1D t{1.0 / res, res};
    coef.assign(static_cast<std::size_t>(N()) * 27, 0.0);
    for (int z = 0; z <= res; ++z)
      for (int y = 0; y <= res; ++y)
        for (int x = 0; x <= res; ++x) {
          double* c = &coef[static_cast<std::size_t>(Idx(x, y, z)) * 27];
          for (int o = 0; o < 27; ++o) {
            const int a = x + Ox(o), b = y + Oy(o), e = z + Oz(o);
            if (a < 0 || b < 0 || e < 0 || a > res || b > res || e > res) continue;
            c[o] = t.S(x, Ox(o)) * t.M(y, Oy(o)) * t.M(z, Oz(o)) + t.M(x, Ox(o)) * t.S(y, Oy(o)) * t.M(z, Oz(o)) +
                   t.M(x, Ox(o)) * t.M(y, Oy(o)) * t.S(z, Oz(o));
          }
        }
    if (beta <= 0) return;
    const std::size_t np = idx ? idx->size() : pts.size();
    for (std::size_t s = 0; s < np; ++s) {
      int c[3];
      double w[8];
      CellOf(pts[idx ? static_cast<std::size_t>((*idx)[s]) : s], res, c, w);
      const double bc = count ? beta * (*count)[s] : beta;
      for (int q1 = 0; q1 < 8; ++q1) {
        const int i = Idx(c[0] + (q1 & 1), c[1] + ((q1 >> 1) & 1), c[2] + ((q1 >> 2) & 1));
        for (int q2 = 0; q2 < 8; ++q2) {
          const int o = ((q2 & 1) - (q1 & 1) + 1) + 3 * (((q2 >> 1) & 1) - ((q1 >> 1) & 1) + 1) +
                        9 * (((q2 >> 2) & 1) - ((q1 >> 2) & 1) + 1);
          coef[static_cast<std::size_t>(i) * 27 + o] += bc * w[q1] * w[q2];
        }
      }
    }
  }
  void Apply(const std::vector<double>& v, std::vector<double>& out) const {
    out.assign(N(), 0.0);
    const int r1 = res + 1;
    ParallelFor(r1, [&](std::int64_t z0, std::int64_t z1) {
      for (int z = static_cast<int>(z0); z < z1; ++z)
        for (int y = 0; y <= res; ++y)
          for (int x = 0; x <= res; ++x) {
            const int i = Idx(x, y, z);
            const double* c = &coef[static_cast<std::size_t>(i) * 27];
            double acc = 0;
            for (int o = 0; o < 27; ++o)
              if (c[o] != 0) acc += c[o] * v[i + Ox(o) + r1 * (Oy(o) + r1 * Oz(o))];
            out[i] = acc;
          }
    }, SliceGrain(std::int64_t(r1) * r1 * 27));
  }
  double Diag(int i) const { return coef[static_cast<std::size_t>(i) * 27 + 13]; }
};

// Restriction (P^T, the transpose of trilinear prolongation) from a complete
// grid of resolution 2r to one of resolution r, and prolongation back.
inline void Restrict(int r, const std::vector<double>& fine, std::vector<double>& coarse) {
  const int f1 = 2 * r + 1, c1 = r + 1;
  coarse.assign(static_cast<std::size_t>(c1) * c1 * c1, 0.0);
  static const double w1[3] = {0.5, 1.0, 0.5};
  // By coarse z-slices in parallel (each entry its own sum: the same bits).
  ParallelFor(r + 1, [&](std::int64_t z0, std::int64_t z1) {
    for (int z = static_cast<int>(z0); z < z1; ++z)
      for (int y = 0; y <= r; ++y)
        for (int x = 0; x <= r; ++x) {
          double acc = 0;
          for (int dz = -1; dz <= 1; ++dz) {
            const int Z = 2 * z + dz;
            if (Z < 0 || Z > 2 * r) continue;
            for (int dy = -1; dy <= 1; ++dy) {
              const int Y = 2 * y + dy;
              if (Y < 0 || Y > 2 * r) continue;
              for (int dx = -1; dx <= 1; ++dx) {
                const int X = 2 * x + dx;
                if (X < 0 || X > 2 * r) continue;
                acc += w1[dx + 1] * w1[dy + 1] * w1[dz + 1] * fine[X + f1 * (Y + f1 * Z)];
              }
            }
          }
          coarse[x + c1 * (y + c1 * z)] = acc;
        }
  }, SliceGrain(c1 * c1 * 27));
}

inline void ProlongAdd(int r, const std::vector<double>& coarse, std::vector<double>& fine) {
  const int f1 = 2 * r + 1, c1 = r + 1;
  ParallelFor(f1, [&](std::int64_t z0, std::int64_t z1) {
    for (int Z = static_cast<int>(z0); Z < z1; ++Z)
      for (int Y = 0; Y <= 2 * r; ++Y)
        for (int X = 0; X <= 2 * r; ++X) {
          fine[X + f1 * (Y + f1 * Z)] +=
              ParentSum<double>(X, Y, Z, [&](int a, int b, int c) { return coarse[a + c1 * (b + c1 * c)]; });
        }
  }, SliceGrain(f1 * f1 * 8));
}

}  // namespace arcs::spsr_fem
