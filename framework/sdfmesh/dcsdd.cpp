#include "framework/sdfmesh/dcsdd.h"

#include "framework/error.h"
#include "framework/sdfmesh/dc_internal.h"
#include "framework/sdfmesh/sdf_input.h"
#include "framework/spatial/triangle_bvh.h"
#include "framework/util/parallel.h"
#include "framework/util/rng.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace arcs {

namespace {

using namespace dc_detail;

// Closest point of p on the triangle (a, b, c) as barycentric weights of
// a, b, c (region tests on the triangle's Voronoi regions: vertices, edges,
// face). Degenerate triangles fall into an edge or vertex region.
Vec3 ClosestBarycentric(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return Vec3(1, 0, 0);
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return Vec3(0, 1, 0);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double t = d1 / (d1 - d3);
    return Vec3(1 - t, t, 0);
  }
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return Vec3(0, 0, 1);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double t = d2 / (d2 - d6);
    return Vec3(1 - t, 0, t);
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return Vec3(0, 1 - t, t);
  }
  const double denom = va + vb + vc;
  if (!(std::abs(denom) > 0)) return Vec3(1, 0, 0);
  const double v = vb / denom, w = vc / denom;
  return Vec3(1 - v - w, v, w);
}

// Incident faces of every vertex (CSR), in face order.
struct Fans {
  std::vector<int> offset, face;
};
Fans BuildFans(const MatrixX3i& F, int nv) {
  Fans f;
  f.offset.assign(nv + 1, 0);
  for (int t = 0; t < F.rows(); ++t)
    for (int k = 0; k < 3; ++k) ++f.offset[F(t, k) + 1];
  std::partial_sum(f.offset.begin(), f.offset.end(), f.offset.begin());
  f.face.resize(f.offset.back());
  std::vector<int> fill(f.offset.begin(), f.offset.end() - 1);
  for (int t = 0; t < F.rows(); ++t)
    for (int k = 0; k < 3; ++k) f.face[fill[F(t, k)]++] = t;
  return f;
}

}  // namespace

void DcsddOptions::Check() const {
  // Hard limits and sane caps (the dcsdd stage declares the same bounds).
  ARCS_CHECK_OPTION(iterations >= 0 && iterations <= 100000, "iterations", iterations, "in [0, 100000]");
  ARCS_CHECK_OPTION(batch_size >= 1 && batch_size <= 1000000000, "batch_size", batch_size, "in [1, 1e9]");
  ARCS_CHECK_OPTION(band >= 0 && band <= 1e6, "band", band, "in [0, 1e6]");
  ARCS_CHECK_OPTION(drop_distance > 0 && drop_distance <= 1e6, "drop_distance", drop_distance, "in (0, 1e6]");
  ARCS_CHECK_OPTION(dc_weight >= 0 && dc_weight <= 1e6, "dc_weight", dc_weight, "in [0, 1e6]");
  ARCS_CHECK_OPTION(proximal_weight > 0 && proximal_weight <= 1e6, "proximal_weight", proximal_weight,
                    "in (0, 1e6] (> 0 keeps every cell solve well posed)");
  ARCS_CHECK_OPTION(svd_threshold >= 0 && svd_threshold < 1, "svd_threshold", svd_threshold, "in [0, 1)");
  ARCS_CHECK_OPTION(dc_svd_threshold >= 0 && dc_svd_threshold < 1, "dc_svd_threshold", dc_svd_threshold, "in [0, 1)");
  ARCS_CHECK_OPTION(inner_iterations >= 1 && inner_iterations <= 100000, "inner_iterations", inner_iterations,
                    "in [1, 100000]");
  ARCS_CHECK_OPTION(inner_tolerance >= 0 && inner_tolerance <= 1, "inner_tolerance", inner_tolerance, "in [0, 1]");
  ARCS_CHECK_OPTION(tolerance >= 0 && tolerance <= 1, "tolerance", tolerance, "in [0, 1]");
  ARCS_CHECK_OPTION(blend >= 0 && blend <= 1, "blend", blend, "in [0, 1]");
}

Mesh Dcsdd(const SdfSamples& s, const DcsddOptions& o, const Context& ctx, DcsddStats* stats) {
  o.Check();
  CheckSdfToMeshInput(s, "dcsdd", /*need_grid=*/true);
  DcGrid g = BuildDcGrid(s.values, *s.grid, 0.0, o.manifold);
  MatrixX3d V = PlaceDcVertices(s.values, g, /*trilinear=*/false, o.dc_svd_threshold, o.clamp_to_cell);
  const int nv = static_cast<int>(g.vertices.size());
  if (nv == 0 || g.quads.empty())
    throw Error("dcsdd: the zero level set crosses no interior grid edge (the sign changes only on the grid boundary)");
  const double diag = g.Spacing().norm();

  // Vertices of each cell (consecutive ids).
  const std::int64_t num_cells = std::int64_t{g.cells[0]} * g.cells[1] * g.cells[2];
  std::vector<int> cell_first(num_cells, -1), cell_count(num_cells, 0);
  for (int v = 0; v < nv; ++v) {
    if (cell_first[g.vertices[v].cell] < 0) cell_first[g.vertices[v].cell] = v;
    ++cell_count[g.vertices[v].cell];
  }

  // Colour classes (parity of the cell's i, j, k) for the Gauss-Seidel sweep.
  std::array<std::vector<int>, 8> by_color;
  for (int v = 0; v < nv; ++v) {
    const std::int64_t c = g.vertices[v].cell;
    const std::int64_t i = c % g.cells[0], j = (c / g.cells[0]) % g.cells[1], k = c / (std::int64_t{g.cells[0]} * g.cells[1]);
    by_color[(i & 1) | ((j & 1) << 1) | ((k & 1) << 2)].push_back(v);
  }

  // Samples near the surface; the others top the batch up at random.
  std::vector<std::int64_t> near, far;
  for (std::int64_t i = 0; i < s.Size(); ++i) (std::abs(s.values[i]) < o.band * diag ? near : far).push_back(i);
  Rng rng(o.seed);
  // Partial Fisher-Yates: the first k entries of *pool become a uniform
  // random k-subset (the pool stays a permutation, so later draws go on).
  auto draw = [&](std::vector<std::int64_t>* pool, std::int64_t k) {
    k = std::min<std::int64_t>(k, pool->size());
    for (std::int64_t i = 0; i < k; ++i) {
      const std::int64_t j = i + static_cast<std::int64_t>(rng.UniformInt(pool->size() - i));
      std::swap((*pool)[i], (*pool)[j]);
    }
    return k;
  };

  double inner_total = 0;
  std::int64_t used_last = 0;
  double residual_first = NAN;
  std::vector<std::int64_t> batch;
  std::vector<int> owner;
  // One pass: closest points of a batch on the current mesh and their owners;
  // returns the mean |distance - radius| of the kept samples.
  auto assign = [&](const MatrixX3i& F) {
    batch.clear();
    if (static_cast<std::int64_t>(near.size()) >= o.batch_size) {
      const std::int64_t k = draw(&near, o.batch_size);
      batch.assign(near.begin(), near.begin() + k);
    } else {
      batch = near;
      const std::int64_t k = draw(&far, o.batch_size - static_cast<std::int64_t>(near.size()));
      batch.insert(batch.end(), far.begin(), far.begin() + k);
    }
    std::sort(batch.begin(), batch.end());  // grid order: coherent closest-point queries
    const std::int64_t m = static_cast<std::int64_t>(batch.size());
    MatrixX3d Q(m, 3);
    for (std::int64_t j = 0; j < m; ++j) Q.row(j) = s.points.row(batch[j]).head<3>();
    Mesh cur;
    cur.V = V;
    cur.F = F;
    const TriangleBvh bvh(cur);
    VectorXd sq;
    MatrixX3d cp;
    Eigen::VectorXi face;
    bvh.ClosestPoints(Q, &sq, &cp, &face);
    owner.assign(m, -1);
    std::vector<double> res(m, 0.0);
    ParallelFor(m, [&](std::int64_t b, std::int64_t e) {
      for (std::int64_t j = b; j < e; ++j) {
        const double d = std::sqrt(sq[j]), r = std::abs(s.values[batch[j]]);
        if (face[j] < 0 || d - r > o.drop_distance * diag) continue;
        const Vec3 q = cp.row(j).transpose();
        const std::int64_t cell = g.CellOf(q);
        int v = -1;
        if (cell_count[cell] == 1) {
          v = cell_first[cell];
        } else if (cell_count[cell] > 1) {  // manifold DC: the cell's sheet on the closest face, if any
          v = cell_first[cell];
          for (int k = 0; k < 3; ++k) {
            const int fv = F(face[j], k);
            if (fv >= cell_first[cell] && fv < cell_first[cell] + cell_count[cell]) v = fv;
          }
        } else {  // the point left the cells with vertices: the closest triangle's nearest vertex
          double best = INFINITY;
          for (int k = 0; k < 3; ++k) {
            const int fv = F(face[j], k);
            const double dd = (V.row(fv).transpose() - q).squaredNorm();
            if (dd < best) best = dd, v = fv;
          }
        }
        owner[j] = v;
        res[j] = std::abs(d - r);
      }
    }, 1024);
    double sum = 0;
    std::int64_t kept = 0;
    for (std::int64_t j = 0; j < m; ++j)
      if (owner[j] >= 0) sum += res[j], ++kept;
    used_last = kept;
    return kept ? sum / kept : 0.0;
  };

  int it = 0;
  for (; it < o.iterations; ++it) {
    ctx.CheckStop();
    const MatrixX3d V_before = V;
    const MatrixX3i F = TriangulateQuads(g.quads, V);
    const double residual = assign(F);
    if (it == 0) residual_first = residual;
    // The samples of each vertex, in batch order.
    std::vector<int> off(nv + 1, 0);
    for (int v : owner)
      if (v >= 0) ++off[v + 1];
    std::partial_sum(off.begin(), off.end(), off.begin());
    std::vector<std::int64_t> mine(off.back());
    {
      std::vector<int> fill(off.begin(), off.end() - 1);
      for (size_t j = 0; j < owner.size(); ++j)
        if (owner[j] >= 0) mine[fill[owner[j]]++] = batch[j];
    }
    const Fans fans = BuildFans(F, nv);

    // Step 4: every vertex against its spheres, in eight colour classes of
    // cells by the parity of (i, j, k): vertices of one class never share a
    // face, so a class is solved in parallel with the others' latest
    // positions (Gauss-Seidel; the result does not depend on the threads).
    std::vector<int> inner(nv, 0);
    for (int color = 0; color < 8; ++color) {
    const std::vector<int>& members = by_color[color];
    ParallelFor(static_cast<std::int64_t>(members.size()), [&](std::int64_t b, std::int64_t e) {
      for (std::int64_t mi = b; mi < e; ++mi) {
        const int vi = members[mi];
        const DcVertex& vx = g.vertices[vi];
        const Vec3 lo = g.CellMin(vx.cell), hi = g.CellMax(vx.cell);
        Vec3 x = V.row(vi).transpose();
        int steps = 0;
        for (; steps < o.inner_iterations; ++steps) {
          Normal3 q;
          for (int id : vx.edges) {
            const HermiteEdge& he = g.edges[id];
            if (he.n.squaredNorm() > 0) q.AddRow(he.n, he.n.dot(he.p - x), o.dc_weight);
          }
          for (int k = off[vi]; k < off[vi + 1]; ++k) {
            const std::int64_t si = mine[k];
            const Vec3 c = s.points.row(si).head<3>().transpose();
            const double r = std::abs(s.values[si]);
            double best = INFINITY, beta = 0;
            Vec3 best_q = x, best_n = Vec3::Zero();
            for (int fi = fans.offset[vi]; fi < fans.offset[vi + 1]; ++fi) {
              const int t = fans.face[fi];
              // Corners in face order with x in place of this vertex.
              std::array<Vec3, 3> P;
              int self = 0;
              for (int kk = 0; kk < 3; ++kk) {
                const int fv = F(t, kk);
                if (fv == vi) self = kk;
                P[kk] = fv == vi ? x : Vec3(V.row(fv).transpose());
              }
              const Vec3 w = ClosestBarycentric(c, P[0], P[1], P[2]);
              const Vec3 qq = w[0] * P[0] + w[1] * P[1] + w[2] * P[2];
              const double dd = (qq - c).squaredNorm();
              if (dd < best) {
                best = dd;
                beta = w[self];
                best_q = qq;
                best_n = (P[1] - P[0]).cross(P[2] - P[0]);
              }
            }
            if (!(beta > 1e-9)) continue;
            const double d = std::sqrt(best);
            Vec3 u;
            if (d > 1e-12 * diag) {
              u = (best_q - c) / d;
            } else {  // the surface passes through the centre: push along the face normal, away from c's side
              const double len = best_n.norm();
              if (!(len > 0)) continue;
              u = -(s.values[si] > 0 ? 1.0 : -1.0) * best_n / len;
            }
            q.AddRow(beta * u, r - d);
          }
          q.AtA += o.proximal_weight * Eigen::Matrix3d::Identity();
          Vec3 xn = x + SolveAbout(q, Vec3::Zero(), o.svd_threshold);
          if (o.clamp_to_cell) ClampToBox(&xn, lo, hi);
          const double step = (xn - x).norm();
          x = xn;
          if (step <= o.inner_tolerance * diag) {
            ++steps;
            break;
          }
        }
        inner[vi] = steps;
        V.row(vi) = x.transpose();
      }
    }, 64);
    }
    inner_total += std::accumulate(inner.begin(), inner.end(), 0.0) / nv;

    // Step 5: Hermite data towards the planes of the new vertices.
    if (o.blend > 0) {
      ParallelFor(static_cast<std::int64_t>(g.quads.size()), [&](std::int64_t b, std::int64_t e) {
        for (std::int64_t qi = b; qi < e; ++qi) {
          HermiteEdge& he = g.edges[g.quad_edge[qi]];
          Vec3 m = Vec3::Zero();
          for (int v : g.quads[qi]) m += V.row(v).transpose();
          m /= 4.0;
          Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
          for (int v : g.quads[qi]) {
            const Vec3 d = V.row(v).transpose() - m;
            C += d * d.transpose();
          }
          const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(C);
          Vec3 nf = es.eigenvectors().col(0);
          Vec3 ref = he.n;
          if (ref.squaredNorm() == 0) {  // orient from inside to outside along the edge
            ref = Vec3::Zero();
            ref[he.axis] = he.inside_low ? 1.0 : -1.0;
          }
          if (nf.dot(ref) < 0) nf = -nf;
          const Vec3 nb = (1 - o.blend) * he.n + o.blend * nf;
          if (nb.norm() > 0) he.n = nb.normalized();
          // The plane's crossing with the edge line, kept on the edge.
          const std::int64_t nx = g.grid.dims[0], ny = g.grid.dims[1];
          const std::array<std::int64_t, 3> ijk{he.node % nx, (he.node / nx) % ny, he.node / (nx * ny)};
          const Vec3 p0(g.coords[0][ijk[0]], g.coords[1][ijk[1]], g.coords[2][ijk[2]]);
          Vec3 dir = Vec3::Zero();
          dir[he.axis] = g.coords[he.axis][ijk[he.axis] + 1] - g.coords[he.axis][ijk[he.axis]];
          const double denom = nf.dot(dir);
          if (std::abs(denom) > 1e-9 * dir.norm()) {
            const double t = std::clamp(nf.dot(m - p0) / denom, 0.0, 1.0);
            he.p = (1 - o.blend) * he.p + o.blend * (p0 + t * dir);
          }
        }
      }, 1024);
    }
    ctx.Progress(static_cast<double>(it + 1) / o.iterations, "dcsdd");
    if (o.tolerance > 0 && (V - V_before).rowwise().norm().maxCoeff() <= o.tolerance * diag) {
      ++it;
      break;
    }
  }
  MatrixX3i F = TriangulateQuads(g.quads, V);
  if (stats) {
    stats->vertices = nv;
    stats->quads = static_cast<int>(g.quads.size());
    if (o.iterations == 0) residual_first = assign(F);
    stats->initial_sphere_residual = residual_first;
    stats->mean_sphere_residual = o.iterations > 0 ? assign(F) : residual_first;
    stats->spheres_used = used_last;
    stats->iterations = it;
    stats->mean_inner_iterations = it > 0 ? inner_total / it : 0.0;
  }
  return CompactMesh(std::move(V), std::move(F));
}

}  // namespace arcs
