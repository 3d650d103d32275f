// Mesh morphing (Luo et al. §2.4) with active-set sampling and Adam.
#include "framework/voxel/morph.h"

#include "framework/voxel/voxelize.h"

#include "framework/error.h"
#include "framework/geometry/builtin_shapes.h"
#include "framework/spatial/topology.h"
#include "framework/spatial/winding_number.h"
#include "framework/util/parallel.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <set>

namespace arcs {

VectorXd HardOccupancy(const Mesh& mesh, const GridInfo& grid) {
  const MatrixX3d Q = GridNodes(grid);
  VectorXd w = FastWindingNumber(mesh).Eval(Q);
  for (Eigen::Index i = 0; i < w.size(); ++i) w[i] = w[i] > 0.5 ? 1.0 : 0.0;
  return w;
}

double OccupancyIoU(const VectorXd& a, const VectorXd& b) {
  if (a.size() != b.size()) throw Error("OccupancyIoU: grids of different sizes");
  std::int64_t inter = 0, uni = 0;
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    const bool x = a[i] > 0.5, y = b[i] > 0.5;
    inter += x && y;
    uni += x || y;
  }
  return uni == 0 ? 1.0 : static_cast<double>(inter) / static_cast<double>(uni);
}

namespace {

void CheckTarget(const VolumeGrid& t) {
  if (t.info.dim != 3 || t.info.dims[0] < 2 || t.info.dims[1] < 2 || t.info.dims[2] < 2)
    throw Error("morph: the target occupancy must be a 3D grid with at least 2 nodes per axis");
  if (t.values.size() != t.info.NumNodes())
    throw Error("morph: the target grid has " + std::to_string(t.values.size()) + " values for " +
                std::to_string(t.info.NumNodes()) + " nodes");
  if (!t.values.allFinite()) throw Error("morph: the target occupancy has non-finite values");
}

// Occupied nodes' count, centroid and bounding box.
struct OccupiedStats {
  std::int64_t count = 0;
  Vec3 centroid = Vec3::Zero(), lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
};
OccupiedStats Occupied(const VolumeGrid& t) {
  CheckTarget(t);
  const MatrixX3d Q = GridNodes(t.info);
  OccupiedStats s;
  for (Eigen::Index i = 0; i < Q.rows(); ++i) {
    if (!(t.values[i] > 0.5)) continue;
    const Vec3 p = Q.row(i).transpose();
    ++s.count;
    s.centroid += p;
    s.lo = s.lo.cwiseMin(p);
    s.hi = s.hi.cwiseMax(p);
  }
  if (s.count == 0) throw Error("morph: the target occupancy has no occupied node (nothing > 0.5)");
  s.centroid /= static_cast<double>(s.count);
  return s;
}

// Vertex neighbours from the faces' edges (sorted, unique).
std::vector<std::vector<int>> Neighbours(const Mesh& m) {
  std::vector<std::set<int>> s(m.NumVertices());
  for (int f = 0; f < m.NumFaces(); ++f)
    for (int j = 0; j < 3; ++j) {
      const int a = m.F(f, j), b = m.F(f, (j + 1) % 3);
      if (a == b) continue;
      s[a].insert(b);
      s[b].insert(a);
    }
  std::vector<std::vector<int>> n(s.size());
  for (size_t i = 0; i < s.size(); ++i) n[i].assign(s[i].begin(), s[i].end());
  return n;
}

double LaplacianEnergy(const MatrixX3d& V, const std::vector<std::vector<int>>& nb, MatrixX3d* grad) {
  const Eigen::Index n = V.rows();
  MatrixX3d L = MatrixX3d::Zero(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (nb[i].empty()) continue;
    Eigen::RowVector3d m = Eigen::RowVector3d::Zero();
    for (int j : nb[i]) m += V.row(j);
    L.row(i) = V.row(i) - m / static_cast<double>(nb[i].size());
  }
  const double inv_n = n > 0 ? 1.0 / static_cast<double>(n) : 0.0;
  if (grad) {
    // ∂/∂V of (1/n) |L V|² = (2/n) Lᵀ (L V).
    grad->setZero(n, 3);
    for (Eigen::Index i = 0; i < n; ++i) {
      if (nb[i].empty()) continue;
      grad->row(i) += 2.0 * inv_n * L.row(i);
      const double w = 2.0 * inv_n / static_cast<double>(nb[i].size());
      for (int j : nb[i]) grad->row(j) -= w * L.row(i);
    }
  }
  return L.squaredNorm() * inv_n;
}

// Marks nodes whose 6-neighbourhood has a different value of `occ`, then
// dilates the mark `band - 1` times.
void MarkBand(const VectorXd& occ, const GridInfo& g, int band, std::vector<char>* mark) {
  const int nx = g.dims[0], ny = g.dims[1], nz = g.dims[2];
  const std::int64_t sx = 1, sy = nx, sz = static_cast<std::int64_t>(nx) * ny;
  std::vector<char> cur(occ.size(), 0);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const std::int64_t id = i + sy * j + sz * k;
        const bool v = occ[id] > 0.5;
        bool edge = false;
        if (i > 0) edge |= (occ[id - sx] > 0.5) != v;
        if (i + 1 < nx) edge |= (occ[id + sx] > 0.5) != v;
        if (j > 0) edge |= (occ[id - sy] > 0.5) != v;
        if (j + 1 < ny) edge |= (occ[id + sy] > 0.5) != v;
        if (k > 0) edge |= (occ[id - sz] > 0.5) != v;
        if (k + 1 < nz) edge |= (occ[id + sz] > 0.5) != v;
        cur[id] = edge;
      }
  for (int b = 1; b < band; ++b) {
    std::vector<char> next = cur;
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
          const std::int64_t id = i + sy * j + sz * k;
          if (cur[id]) continue;
          next[id] = (i > 0 && cur[id - sx]) || (i + 1 < nx && cur[id + sx]) || (j > 0 && cur[id - sy]) ||
                     (j + 1 < ny && cur[id + sy]) || (k > 0 && cur[id - sz]) || (k + 1 < nz && cur[id + sz]);
        }
    cur.swap(next);
  }
  for (size_t i = 0; i < cur.size(); ++i) (*mark)[i] |= cur[i];
}

}  // namespace

double UniformLaplacianEnergy(const Mesh& mesh, MatrixX3d* grad) {
  CheckMeshIndices(mesh, "UniformLaplacianEnergy");
  return LaplacianEnergy(mesh.V, Neighbours(mesh), grad);
}

Mesh InitialSphere(const VolumeGrid& target, int subdivisions) {
  ARCS_CHECK_OPTION(subdivisions >= 0 && subdivisions <= 7, "subdivisions", subdivisions, "in [0, 7]");
  const OccupiedStats s = Occupied(target);
  const GridInfo& g = target.info;
  const double cell = g.Spacing(0) * g.Spacing(1) * g.Spacing(2);
  const double volume = static_cast<double>(s.count) * cell;
  const double r = std::cbrt(3.0 * volume / (4.0 * std::numbers::pi));
  return MakeIcosphere(r, subdivisions, s.centroid);
}

Mesh FitSourceToTarget(const Mesh& source, const VolumeGrid& target) {
  if (source.Empty() || source.NumVertices() == 0) throw Error("morph: the source mesh is empty");
  CheckMeshIndices(source, "morph source", /*finite=*/true);
  const OccupiedStats s = Occupied(target);
  const Vec3 lo = source.V.colwise().minCoeff().transpose(), hi = source.V.colwise().maxCoeff().transpose();
  const double src_side = (hi - lo).maxCoeff();
  const double dst_side = std::max((s.hi - s.lo).maxCoeff(), target.info.Spacing(0));
  if (!(src_side > 0.0)) throw Error("morph: the source mesh's bounding box is a single point");
  const double scale = dst_side / src_side;
  const Vec3 c_src = 0.5 * (lo + hi), c_dst = 0.5 * (s.lo + s.hi);
  Mesh m = source;
  for (Eigen::Index i = 0; i < m.V.rows(); ++i)
    m.V.row(i) = (c_dst + scale * (Vec3(m.V.row(i).transpose()) - c_src)).transpose();
  return m;
}

const char* MorphResidualName(MorphResidual v) {
  for (const auto& e : kMorphResidualNames)
    if (e.value == v) return e.name;
  return "?";
}

MorphResidual ParseMorphResidual(const std::string& name) {
  return EnumFromName(std::span<const EnumName<MorphResidual>>(kMorphResidualNames), name);
}

void MorphOptions::Check() const {
  // Hard limits and sane caps (the morph stage and `arcs morph` declare the same bounds).
  ARCS_CHECK_OPTION(iterations >= 0 && iterations <= 100000, "iterations", iterations, "in [0, 100000]");
  ARCS_CHECK_OPTION(lr > 0.0 && lr <= 1.0, "lr", lr, "in (0, 1]");
  ARCS_CHECK_OPTION(beta1 >= 0.0 && beta1 < 1.0, "beta1", beta1, "in [0, 1)");
  ARCS_CHECK_OPTION(beta2 >= 0.0 && beta2 < 1.0, "beta2", beta2, "in [0, 1)");
  ARCS_CHECK_OPTION(smooth >= 0.0 && smooth <= 1e9, "smooth", smooth, "in [0, 1e9]");
  ARCS_CHECK_OPTION(batch >= 0 && batch <= 100000000, "batch", batch, "in [0, 1e8] (0 = the whole active set)");
  ARCS_CHECK_OPTION(random_fraction >= 0.0 && random_fraction <= 1.0, "random_fraction", random_fraction,
                    "in [0, 1]");
  ARCS_CHECK_OPTION(band >= 1 && band <= 64, "band", band, "in [1, 64]");
  ARCS_CHECK_OPTION(refresh_every >= 1 && refresh_every <= 100000, "refresh_every", refresh_every, "in [1, 100000]");
  ARCS_CHECK_OPTION(softening_voxels >= 0.0 && softening_voxels <= 100.0, "softening", softening_voxels,
                    "in [0, 100] voxels");
  loss.Check();
}

MorphResult MorphToOccupancy(const Mesh& source, const VolumeGrid& target, const MorphOptions& options,
                             Context& ctx, const std::function<void(const MorphLogEntry&)>& on_log) {
  options.Check();
  CheckTarget(target);
  if (source.Empty()) throw Error("morph: the source mesh has no faces");
  CheckMeshIndices(source, "morph source", /*finite=*/true);
  (void)Occupied(target);  // throws if nothing is occupied
  const auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };

  const GridInfo& g = target.info;
  const MatrixX3d nodes = GridNodes(g);
  const std::int64_t n_nodes = nodes.rows();
  VectorXd t = target.values;
  for (Eigen::Index i = 0; i < t.size(); ++i) t[i] = t[i] > 0.5 ? 1.0 : 0.0;
  std::vector<char> target_band(n_nodes, 0);
  MarkBand(t, g, options.band, &target_band);

  Mesh mesh = source;
  const auto nb = Neighbours(mesh);
  Rng rng = ctx.MakeRng("morph");
  MatrixX3d m1 = MatrixX3d::Zero(mesh.V.rows(), 3), m2 = m1;
  std::vector<int> active;
  MorphResult res;
  double last_loss = 0.0;

  auto refresh = [&](int it) {
    const VectorXd h = HardOccupancy(mesh, g);
    const double iou = OccupancyIoU(h, t);
    std::vector<char> mark = target_band;
    MarkBand(h, g, options.band, &mark);
    active.clear();
    for (std::int64_t i = 0; i < n_nodes; ++i)
      if (mark[i] || (h[i] > 0.5) != (t[i] > 0.5)) active.push_back(static_cast<int>(i));
    MorphLogEntry e{it, iou, last_loss, static_cast<int>(active.size()), elapsed()};
    res.log.push_back(e);
    if (on_log) on_log(e);
    return iou;
  };

  res.initial_iou = refresh(0);
  const int n_random_max = static_cast<int>(std::lround(options.batch * options.random_fraction));
  for (int it = 1; it <= options.iterations; ++it) {
    ctx.CheckStop();
    // The batch: a partial Fisher–Yates draw from the active set + uniform nodes.
    const int want = options.batch == 0 ? static_cast<int>(active.size()) : options.batch - n_random_max;
    const int n_act = std::min<int>(want, static_cast<int>(active.size()));
    for (int i = 0; i < n_act; ++i) {
      const int j = i + static_cast<int>(rng.UniformInt(active.size() - i));
      std::swap(active[i], active[j]);
    }
    const int n_rand = options.batch == 0 ? 0 : n_random_max;
    const int nb_q = n_act + n_rand;
    if (nb_q == 0) break;  // nothing to fit (cannot happen with an occupied target)
    MatrixX3d Q(nb_q, 3);
    VectorXd tq(nb_q);
    for (int i = 0; i < nb_q; ++i) {
      const std::int64_t id = i < n_act ? active[i] : static_cast<std::int64_t>(rng.UniformInt(n_nodes));
      Q.row(i) = nodes.row(id);
      tq[i] = t[id];
    }
    // Data term: λ_q = (1/|S|) ∂ℓ/∂o · ∂o/∂w.
    SoftOccupancyOptions so = options.loss.occupancy;
    so.softening = options.softening_voxels * g.Spacing(0);
    VectorXd lambda(nb_q);
    double data_loss = 0.0;
    if (options.residual == MorphResidual::kSoft) {
      const VectorXd w = WindingNumbers(mesh, Q, so.form, so.softening);
      for (int i = 0; i < nb_q; ++i) {
        double dodw = 0.0, dldo = 0.0;
        const double o = OccupancyFromWinding(w[i], so, &dodw);
        data_loss += OccupancyLossTerm(o, tq[i], options.loss.loss, &dldo);
        lambda[i] = dldo * dodw / nb_q;
      }
    } else {
      const VectorXd w = FastWindingNumber(mesh).Eval(Q);
      for (int i = 0; i < nb_q; ++i) {
        const double o = w[i] > 0.5 ? 1.0 : 0.0;
        double dldo = 0.0;
        data_loss += OccupancyLossTerm(o, tq[i], OccupancyLossKind::kMse, &dldo);
        lambda[i] = dldo / nb_q;
      }
    }
    data_loss /= nb_q;
    MatrixX3d grad = WindingNumberVjp(mesh, Q, lambda, so.form, so.softening);
    double loss = data_loss;
    if (options.smooth > 0.0) {
      MatrixX3d gs;
      loss += options.smooth * LaplacianEnergy(mesh.V, nb, &gs);
      grad += options.smooth * gs;
    }
    last_loss = loss;
    // Adam (Kingma & Ba 2015), bias-corrected.
    m1 = options.beta1 * m1 + (1.0 - options.beta1) * grad;
    m2 = options.beta2 * m2 + (1.0 - options.beta2) * grad.cwiseAbs2();
    const double c1 = 1.0 - std::pow(options.beta1, it), c2 = 1.0 - std::pow(options.beta2, it);
    mesh.V.array() -= options.lr * (m1.array() / c1) / ((m2.array() / c2).sqrt() + 1e-12);
    if (!mesh.V.allFinite()) throw Error("morph: the optimisation diverged (non-finite vertices) at iteration " +
                                         std::to_string(it) + "; lower lr");
    if (it % options.refresh_every == 0 || it == options.iterations) refresh(it);
    ctx.Progress(static_cast<double>(it) / options.iterations, "morph");
  }
  res.final_iou = res.log.back().iou;
  res.iterations = options.iterations;
  res.mesh = std::move(mesh);
  res.seconds = elapsed();
  return res;
}

}  // namespace arcs
