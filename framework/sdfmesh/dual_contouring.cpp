#include "framework/sdfmesh/dual_contouring.h"

#include "framework/error.h"
#include "framework/geometry/marching_cubes.h"
#include "framework/sdfmesh/dc_internal.h"
#include "framework/util/parallel.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <string>

namespace arcs {

namespace dc_detail {
namespace {

// Per sign configuration (bit c set = cube corner c inside): the sheet of
// each cube edge (-1 = not crossed) and the number of sheets. A sheet is a
// connected patch of marching cubes' case triangles (MC's face rule resolves
// ambiguous faces, so neighbouring cells agree on which edges share a sheet).
struct SheetTable {
  std::array<std::array<signed char, 12>, 256> sheet{};
  std::array<int, 256> count{};
  // Cube edge along `axis` whose base corner is `corner` (-1 otherwise).
  std::array<std::array<signed char, 8>, 3> edge_at{};
};

const SheetTable& Sheets() {
  static const SheetTable table = [] {
    SheetTable t;
    for (auto& a : t.edge_at) a.fill(-1);
    for (int e = 0; e < 12; ++e) t.edge_at[e / 4][detail::MarchingCubesEdgeCorner(e)] = static_cast<signed char>(e);
    for (int config = 0; config < 256; ++config) {
      std::array<int, 12> parent;
      for (int e = 0; e < 12; ++e) parent[e] = e;
      auto find = [&](int e) {
        while (parent[e] != e) e = parent[e] = parent[parent[e]];
        return e;
      };
      std::array<bool, 12> crossed{};
      for (const auto& tri : detail::MarchingCubesCase(config)) {
        for (int k = 0; k < 3; ++k) crossed[tri[k]] = true;
        const int r0 = find(tri[0]);
        for (int k = 1; k < 3; ++k) parent[find(tri[k])] = r0;
      }
      // Sheets numbered in order of their smallest cube edge.
      std::array<int, 12> id;
      id.fill(-1);
      int count = 0;
      for (int e = 0; e < 12; ++e) {
        t.sheet[config][e] = -1;
        if (!crossed[e]) continue;
        const int r = find(e);
        if (id[r] < 0) id[r] = count++;
        t.sheet[config][e] = static_cast<signed char>(id[r]);
      }
      t.count[config] = count;
    }
    return t;
  }();
  return table;
}

std::vector<double> AxisCoords(const GridInfo& g, int a) {
  std::vector<double> c(g.dims[a]);
  const double h = g.Spacing(a);
  for (int i = 0; i < g.dims[a]; ++i) c[i] = g.min[a] + i * h;
  c.back() = g.max[a];
  return c;
}

}  // namespace

Vec3 DcGrid::Spacing() const { return Vec3(grid.Spacing(0), grid.Spacing(1), grid.Spacing(2)); }

Vec3 DcGrid::CellMin(std::int64_t cell) const {
  const std::int64_t i = cell % cells[0], j = (cell / cells[0]) % cells[1], k = cell / (std::int64_t{cells[0]} * cells[1]);
  return Vec3(coords[0][i], coords[1][j], coords[2][k]);
}

Vec3 DcGrid::CellMax(std::int64_t cell) const {
  const std::int64_t i = cell % cells[0], j = (cell / cells[0]) % cells[1], k = cell / (std::int64_t{cells[0]} * cells[1]);
  return Vec3(coords[0][i + 1], coords[1][j + 1], coords[2][k + 1]);
}

std::int64_t DcGrid::CellOf(const Vec3& x) const {
  std::array<std::int64_t, 3> c{};
  for (int a = 0; a < 3; ++a) {
    const double u = (x[a] - grid.min[a]) / grid.Spacing(a);
    c[a] = std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor(std::isfinite(u) ? u : 0.0)), 0, cells[a] - 1);
  }
  return c[0] + std::int64_t{cells[0]} * (c[1] + std::int64_t{cells[1]} * c[2]);
}

DcGrid BuildDcGrid(const VectorXd& values, const GridInfo& grid, double iso, bool manifold) {
  if (grid.dim != 3) throw Error("dual contouring: the grid must be 3D (grid.dim = " + std::to_string(grid.dim) + ")");
  for (int a = 0; a < 3; ++a) {
    if (grid.dims[a] < 2)
      throw Error("dual contouring: grid.dims[" + std::to_string(a) + "] = " + std::to_string(grid.dims[a]) + ": must be >= 2");
    if (!(grid.max[a] > grid.min[a]))
      throw Error("dual contouring: the grid's extent along axis " + std::to_string(a) + " must be positive");
  }
  if (grid.NumNodes() != values.size())
    throw Error("dual contouring: the grid has " + std::to_string(grid.NumNodes()) + " nodes but there are " +
                std::to_string(values.size()) + " values");
  if (!values.allFinite()) throw Error("dual contouring: the values must be finite");
  if (!std::isfinite(iso)) throw Error("dual contouring: the isovalue must be finite");

  DcGrid g;
  g.grid = grid;
  for (int a = 0; a < 3; ++a) {
    g.cells[a] = grid.dims[a] - 1;
    g.coords[a] = AxisCoords(grid, a);
  }
  const int nx = grid.dims[0], ny = grid.dims[1], nz = grid.dims[2];
  const std::int64_t nxy = std::int64_t{nx} * ny, n = nxy * nz;
  const std::array<std::int64_t, 3> stride{1, nx, nxy};
  std::vector<std::uint8_t> in(n);
  for (std::int64_t i = 0; i < n; ++i) in[i] = values[i] < iso ? 1 : 0;

  // Sign-changing edges in node order, then axis.
  std::vector<int> edge_id(3 * n, -1);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const std::array<int, 3> ijk{i, j, k};
        const std::int64_t node = i + nx * (j + std::int64_t{ny} * k);
        for (int a = 0; a < 3; ++a) {
          if (ijk[a] + 1 >= grid.dims[a] || in[node] == in[node + stride[a]]) continue;
          edge_id[3 * node + a] = static_cast<int>(g.edges.size());
          HermiteEdge e;
          e.node = node;
          e.axis = a;
          e.inside_low = in[node];
          g.edges.push_back(e);
        }
      }
  const Vec3 h = g.Spacing();
  auto node_ijk = [&](std::int64_t node) {
    return std::array<int, 3>{static_cast<int>(node % nx), static_cast<int>((node / nx) % ny),
                              static_cast<int>(node / nxy)};
  };
  // Crossing points and per-edge normals: along the edge the exact difference,
  // across it central differences (one-sided on the grid boundary) at both
  // ends, linearly interpolated (the mean of the cells' trilinear gradients).
  ParallelFor(static_cast<std::int64_t>(g.edges.size()), [&](std::int64_t b, std::int64_t e_end) {
    for (std::int64_t ei = b; ei < e_end; ++ei) {
      HermiteEdge& e = g.edges[ei];
      const int a = e.axis;
      const std::int64_t n1 = e.node + stride[a];
      const double v0 = values[e.node], v1 = values[n1];
      const double t = std::clamp((iso - v0) / (v1 - v0), 0.0, 1.0);
      const auto ijk = node_ijk(e.node);
      Vec3 p(g.coords[0][ijk[0]], g.coords[1][ijk[1]], g.coords[2][ijk[2]]);
      p[a] += t * (g.coords[a][ijk[a] + 1] - g.coords[a][ijk[a]]);
      e.p = p;
      Vec3 grad;
      grad[a] = (v1 - v0) / (g.coords[a][ijk[a] + 1] - g.coords[a][ijk[a]]);
      for (int d = 1; d < 3; ++d) {
        const int b2 = (a + d) % 3;
        auto diff = [&](std::int64_t node, int coord) {
          const bool lo = coord > 0, hi = coord + 1 < grid.dims[b2];
          const double vm = lo ? values[node - stride[b2]] : values[node];
          const double vp = hi ? values[node + stride[b2]] : values[node];
          return (vp - vm) / ((lo && hi ? 2.0 : 1.0) * h[b2]);
        };
        grad[b2] = (1 - t) * diff(e.node, ijk[b2]) + t * diff(n1, ijk[b2]);
      }
      const double len = grad.norm();
      e.n = len > 0 && std::isfinite(len) ? Vec3(grad / len) : Vec3::Zero();
    }
  }, 4096);

  // Active cells and their vertices (cell order z, y, x; sheet order).
  const SheetTable& st = Sheets();
  const std::int64_t cx = g.cells[0], cy = g.cells[1], cz = g.cells[2];
  std::vector<int> first_vertex(cx * cy * cz, -1);
  auto config_of = [&](std::int64_t i, std::int64_t j, std::int64_t k) {
    const std::int64_t base = i + nx * (j + std::int64_t{ny} * k);
    int c = 0;
    for (int corner = 0; corner < 8; ++corner) {
      const std::int64_t node = base + (corner & 1) * stride[0] + ((corner >> 1) & 1) * stride[1] +
                                ((corner >> 2) & 1) * stride[2];
      c |= in[node] << corner;
    }
    return c;
  };
  for (std::int64_t k = 0; k < cz; ++k)
    for (std::int64_t j = 0; j < cy; ++j)
      for (std::int64_t i = 0; i < cx; ++i) {
        const int config = config_of(i, j, k);
        if (config == 0 || config == 255) continue;
        const std::int64_t cell = i + cx * (j + cy * k);
        const std::int64_t base = i + nx * (j + std::int64_t{ny} * k);
        const int sheets = st.count[config];
        if (sheets > 1) ++g.multi_sheet_cells;
        first_vertex[cell] = static_cast<int>(g.vertices.size());
        const int nv = manifold ? sheets : 1;
        for (int s = 0; s < nv; ++s) {
          DcVertex v;
          v.cell = cell;
          for (int ce = 0; ce < 12; ++ce) {
            if (st.sheet[config][ce] < 0 || (manifold && st.sheet[config][ce] != s)) continue;
            const int corner = detail::MarchingCubesEdgeCorner(ce);
            const std::int64_t node = base + (corner & 1) * stride[0] + ((corner >> 1) & 1) * stride[1] +
                                      ((corner >> 2) & 1) * stride[2];
            v.edges.push_back(edge_id[3 * node + ce / 4]);
            v.cube_edge.push_back(static_cast<signed char>(ce));
          }
          g.vertices.push_back(std::move(v));
        }
      }

  // One quad per interior sign-changing edge: the cells around it, counter-
  // clockwise about +axis (normal +axis) when the low end is inside.
  static const int kCycle[4][2] = {{-1, -1}, {0, -1}, {0, 0}, {-1, 0}};
  for (size_t ei = 0; ei < g.edges.size(); ++ei) {
    const HermiteEdge& e = g.edges[ei];
    const int a = e.axis, b = (a + 1) % 3, c = (a + 2) % 3;
    const auto ijk = node_ijk(e.node);
    if (ijk[b] < 1 || ijk[b] > g.cells[b] - 1 || ijk[c] < 1 || ijk[c] > g.cells[c] - 1) continue;
    std::array<int, 4> q{};
    for (int m = 0; m < 4; ++m) {
      std::array<std::int64_t, 3> cc{ijk[0], ijk[1], ijk[2]};
      cc[b] += kCycle[m][0];
      cc[c] += kCycle[m][1];
      const std::int64_t cell = cc[0] + cx * (cc[1] + cy * cc[2]);
      int v = first_vertex[cell];
      if (manifold) {
        const int corner = ((-kCycle[m][0]) << b) | ((-kCycle[m][1]) << c);
        const int ce = st.edge_at[a][corner];
        v += st.sheet[config_of(cc[0], cc[1], cc[2])][ce];
      }
      q[m] = v;
    }
    if (!e.inside_low) std::swap(q[1], q[3]);
    g.quads.push_back(q);
    g.quad_edge.push_back(static_cast<int>(ei));
  }
  return g;
}

Vec3 TrilinearGradient(const VectorXd& values, const DcGrid& g, std::int64_t cell, const Vec3& x) {
  const int nx = g.grid.dims[0], ny = g.grid.dims[1];
  const std::int64_t i = cell % g.cells[0], j = (cell / g.cells[0]) % g.cells[1],
                     k = cell / (std::int64_t{g.cells[0]} * g.cells[1]);
  const std::array<std::int64_t, 3> ijk{i, j, k};
  Vec3 u, h;
  for (int a = 0; a < 3; ++a) {
    h[a] = g.coords[a][ijk[a] + 1] - g.coords[a][ijk[a]];
    u[a] = std::clamp((x[a] - g.coords[a][ijk[a]]) / h[a], 0.0, 1.0);
  }
  const std::int64_t base = i + nx * (j + std::int64_t{ny} * k);
  const std::array<std::int64_t, 3> stride{1, nx, std::int64_t{nx} * ny};
  Vec3 grad = Vec3::Zero();
  for (int corner = 0; corner < 8; ++corner) {
    const std::array<int, 3> bit{corner & 1, (corner >> 1) & 1, (corner >> 2) & 1};
    const double v = values[base + bit[0] * stride[0] + bit[1] * stride[1] + bit[2] * stride[2]];
    for (int a = 0; a < 3; ++a) {
      double w = bit[a] ? 1.0 : -1.0;  // d/du of u or (1 - u)
      for (int o = 0; o < 3; ++o)
        if (o != a) w *= bit[o] ? u[o] : 1.0 - u[o];
      grad[a] += w * v;
    }
  }
  return Vec3(grad[0] / h[0], grad[1] / h[1], grad[2] / h[2]);
}

Vec3 SolveAbout(const Normal3& q, const Vec3& center, double threshold) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(q.AtA);
  const Vec3 lambda = es.eigenvalues();  // ascending
  if (!(lambda[2] > 0)) return center;
  const double sigma_max = std::sqrt(lambda[2]);
  const Vec3 rhs = q.Atb - q.AtA * center;
  Vec3 y = Vec3::Zero();
  for (int k = 0; k < 3; ++k) {
    if (!(lambda[k] > 0) || std::sqrt(lambda[k]) <= threshold * sigma_max) continue;
    const Vec3 v = es.eigenvectors().col(k);
    y += v * (v.dot(rhs) / lambda[k]);
  }
  return center + y;
}

bool ClampToBox(Vec3* x, const Vec3& lo, const Vec3& hi) {
  const Vec3 c = x->cwiseMax(lo).cwiseMin(hi);
  const bool moved = c != *x;
  *x = c;
  return moved;
}

MatrixX3i TriangulateQuads(const std::vector<std::array<int, 4>>& quads, const MatrixX3d& V) {
  MatrixX3i F(2 * quads.size(), 3);
  for (size_t i = 0; i < quads.size(); ++i) {
    const auto& q = quads[i];
    const double d02 = (V.row(q[0]) - V.row(q[2])).squaredNorm(), d13 = (V.row(q[1]) - V.row(q[3])).squaredNorm();
    if (d02 <= d13) {
      F.row(2 * i) << q[0], q[1], q[2];
      F.row(2 * i + 1) << q[0], q[2], q[3];
    } else {
      F.row(2 * i) << q[0], q[1], q[3];
      F.row(2 * i + 1) << q[1], q[2], q[3];
    }
  }
  return F;
}

Mesh CompactMesh(MatrixX3d V, MatrixX3i F) {
  std::vector<int> remap(V.rows(), -1);
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) remap[F(f, k)] = 0;
  int next = 0;
  for (auto& r : remap)
    if (r == 0) r = next++;
  Mesh m;
  m.V.resize(next, 3);
  for (int v = 0; v < V.rows(); ++v)
    if (remap[v] >= 0) m.V.row(remap[v]) = V.row(v);
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) F(f, k) = remap[F(f, k)];
  m.F = std::move(F);
  return m;
}

MatrixX3d PlaceDcVertices(const VectorXd& values, const DcGrid& g, bool trilinear, double svd_threshold,
                          bool clamp_to_cell, std::vector<std::uint8_t>* clamped_out) {
  const std::int64_t nv = static_cast<std::int64_t>(g.vertices.size());
  MatrixX3d V(nv, 3);
  std::vector<std::uint8_t> clamped(nv, 0);
  ParallelFor(nv, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t vi = b; vi < e; ++vi) {
      const DcVertex& v = g.vertices[vi];
      Normal3 q;
      Vec3 mass = Vec3::Zero();
      for (int id : v.edges) mass += g.edges[id].p;
      mass /= static_cast<double>(v.edges.size());
      for (int id : v.edges) {
        const HermiteEdge& he = g.edges[id];
        Vec3 n = he.n;
        if (trilinear) {
          const Vec3 grad = TrilinearGradient(values, g, v.cell, he.p);
          const double len = grad.norm();
          n = len > 0 ? Vec3(grad / len) : Vec3::Zero();
        }
        if (n.squaredNorm() == 0) continue;
        q.AddRow(n, n.dot(he.p));
      }
      Vec3 x = SolveAbout(q, mass, svd_threshold);
      if (clamp_to_cell) clamped[vi] = ClampToBox(&x, g.CellMin(v.cell), g.CellMax(v.cell));
      V.row(vi) = x.transpose();
    }
  }, 256);
  if (clamped_out) *clamped_out = std::move(clamped);
  return V;
}

}  // namespace dc_detail

void DualContouringOptions::Check() const {
  if (!std::isfinite(isovalue)) throw OptionError("isovalue = " + std::to_string(isovalue) + ": must be finite");
  ARCS_CHECK_OPTION(svd_threshold >= 0.0 && svd_threshold < 1.0, "svd_threshold", svd_threshold, "in [0, 1)");
}

Mesh DualContouring(const VectorXd& values, const GridInfo& grid, const DualContouringOptions& o,
                    DualContouringStats* stats) {
  using namespace dc_detail;
  o.Check();
  const DcGrid g = BuildDcGrid(values, grid, o.isovalue, o.manifold);
  const std::int64_t nv = static_cast<std::int64_t>(g.vertices.size());
  std::vector<std::uint8_t> clamped;
  MatrixX3d V = PlaceDcVertices(values, g, o.normals == DualContouringOptions::Normals::kTrilinear, o.svd_threshold,
                                o.clamp_to_cell, &clamped);
  MatrixX3i F = TriangulateQuads(g.quads, V);
  if (stats) {
    stats->vertices = static_cast<int>(nv);
    stats->quads = static_cast<int>(g.quads.size());
    stats->clamped = static_cast<int>(std::count(clamped.begin(), clamped.end(), 1));
    stats->multi_sheet_cells = g.multi_sheet_cells;
  }
  return CompactMesh(std::move(V), std::move(F));
}

}  // namespace arcs
