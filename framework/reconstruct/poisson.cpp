// Screened Poisson reconstruction: input validation, the automatic depth rule
// and the post-processing (orientation, canonical order) around the PCL
// back-end in poisson_pcl.cpp.
#include "framework/reconstruct/poisson.h"

#include "framework/error.h"
#include "framework/reconstruct/poisson_open3d.h"
#include "framework/reconstruct/poisson_pcl.h"
#include "framework/reconstruct/spsr.h"
#include "framework/spatial/knn.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <unordered_set>
#include <vector>

namespace arcs {

void PoissonOptions::Check() const {
  ARCS_CHECK_OPTION(depth == 0 || (depth >= 2 && depth <= 12), "depth", depth,
                    "0 (automatic) or an integer in [2, 12]");
  ARCS_CHECK_OPTION(depth_offset >= -8 && depth_offset <= 4, "depth_offset", depth_offset, "an integer in [-8, 4]");
  ARCS_CHECK_OPTION(min_depth >= 0 && min_depth <= 12, "min_depth", min_depth,
                    "an integer in [0, 12]");
  ARCS_CHECK_OPTION(std::isfinite(point_weight) && point_weight >= 0.0 && point_weight <= 1e6,
                    "point_weight", point_weight, "in [0, 1e6]");
  ARCS_CHECK_OPTION(open_retries >= 0 && open_retries <= 10, "open_retries", open_retries, "in [0, 10]");
  ARCS_CHECK_OPTION(retry_weight_factor > 0.0 && retry_weight_factor < 1.0, "retry_weight_factor",
                    retry_weight_factor, "in (0, 1)");
  ARCS_CHECK_OPTION(std::isfinite(samples_per_node) && samples_per_node >= 0.5 &&
                        samples_per_node <= 100.0,
                    "samples_per_node", samples_per_node, "in [0.5, 100]");
  ARCS_CHECK_OPTION(std::isfinite(scale) && scale >= 1.01 && scale <= 16.0, "scale", scale,
                    "in [1.01, 16]");
  ARCS_CHECK_OPTION(threads >= 1 && threads <= 256, "threads", threads,
                    "an integer in [1, 256]");
  ARCS_CHECK_OPTION(cg_iters >= 1 && cg_iters <= 10000, "cg_iters", cg_iters, "an integer in [1, 10000]");
  ARCS_CHECK_OPTION(cg_accuracy > 0.0 && cg_accuracy < 1.0, "cg_accuracy", cg_accuracy, "in (0, 1)");
  ARCS_CHECK_OPTION(base_accuracy > 0.0 && base_accuracy < 1.0, "base_accuracy", base_accuracy, "in (0, 1)");
  ARCS_CHECK_OPTION(gs_iters >= 1 && gs_iters <= 10000, "gs_iters", gs_iters, "an integer in [1, 10000]");
  ARCS_CHECK_OPTION(extract_quantile >= 0.0 && extract_quantile <= 1.0, "extract_quantile", extract_quantile,
                    "in [0, 1]");
  ARCS_CHECK_OPTION(std::isfinite(extract_max_cell) && extract_max_cell >= 0.0 && extract_max_cell <= 1e9,
                    "extract_max_cell", extract_max_cell, "in [0, 1e9]");
  ARCS_CHECK_OPTION(std::isfinite(density_scale) && density_scale >= 0.1 && density_scale <= 10.0, "density_scale",
                    density_scale, "in [0.1, 10]");
  ARCS_CHECK_OPTION(std::isfinite(carve_margin) && carve_margin >= 0.0 && carve_margin <= 10.0, "carve_margin",
                    carve_margin, "in [0, 10]");
  if (carve && backend != Backend::kArcs)
    throw OptionError("carve: only the arcs back-end can carve its surface (backend arcs)");
}

PoissonOptions OfficialRftaPoisson() {
  PoissonOptions o;
  o.backend = PoissonOptions::Backend::kArcs;
  o.depth = 10;
  o.scale = 3.2;
  o.samples_per_node = 1.5;
  // PoissonRecon weighs a sample by 4^-depth = 1.5 x its area: 1.5 x the
  // official 10 in our area-per-sample units (docs/poisson.md, session 32).
  o.point_weight = 15.0;
  o.area_normalized = true;
  o.open_retries = 0;
  // PoissonRecon's cascadic relaxation above the complete level:
  // Gauss-Seidel sweeps per level, gs_iters' default 8 being its `iters` 8
  // (the official call's default). docs/poisson.md, "Fine-level solvers"
  // (session 37).
  o.fine_solver = SpsrOptions::FineSolver::kGaussSeidel;
  // PoissonRecon 16/18's placement (docs/poisson.md, sessions 24 and 32): a
  // sample's whole normal at ceil(d_s), and depths from the density its
  // normalised kernel reads (1.5 x our tents').
  o.normal_splat = SpsrOptions::NormalSplat::kCeil;
  o.density_scale = 1.5;
  return o;
}

PoissonOptions RftaTuningPoisson() {
  PoissonOptions o = OfficialRftaPoisson();
  o.normal_splat = SpsrOptions::NormalSplat::kSplit;
  o.density_scale = 1.0;
  o.point_weight = 10.0;
  return o;
}

bool PoissonAvailable() { return poisson_detail::PclAvailable(); }
bool PoissonOpen3dAvailable() { return poisson_detail::Open3dPoissonAvailable(); }

namespace {

constexpr int kMinPoints = 10;
// Boundary loops up to this length are treated as marching-cubes cracks and closed.
constexpr int kMaxCrackEdges = 12;

// Bounding box of validated points.
struct Box {
  Vec3 lo, hi;
  Vec3 Center() const { return 0.5 * (lo + hi); }
  double Extent() const { return (hi - lo).maxCoeff(); }
};

// Validates the input (before PCL sees it: it crashes or silently drops
// points on some of these) and returns the bounding box.
Box ValidateInput(const PointCloud& pc) {
  const Eigen::Index n = pc.P.rows();
  if (n < kMinPoints) {
    throw Error("screened Poisson: needs at least " + std::to_string(kMinPoints) +
                " oriented points, got " + std::to_string(n));
  }
  if (pc.N.rows() != n) {
    throw Error("screened Poisson: needs one normal per point: got " +
                std::to_string(pc.N.rows()) + " normals for " + std::to_string(n) + " points");
  }
  Eigen::Index bad_p = 0, bad_n = 0, zero_n = 0, first_p = -1, first_n = -1, first_zero = -1;
  Box box{Vec3::Constant(std::numeric_limits<double>::infinity()),
          Vec3::Constant(-std::numeric_limits<double>::infinity())};
  for (Eigen::Index i = 0; i < n; ++i) {
    const Vec3 p = pc.P.row(i), nn = pc.N.row(i);
    if (!p.allFinite()) {
      if (bad_p++ == 0) first_p = i;
      continue;
    }
    box.lo = box.lo.cwiseMin(p);
    box.hi = box.hi.cwiseMax(p);
    if (!nn.allFinite()) {
      if (bad_n++ == 0) first_n = i;
    } else if (!(nn.cwiseAbs().maxCoeff() > 0.0)) {
      if (zero_n++ == 0) first_zero = i;
    }
  }
  if (bad_p > 0) {
    throw Error("screened Poisson: " + std::to_string(bad_p) +
                " point(s) with a non-finite coordinate (first: row " + std::to_string(first_p) +
                ")");
  }
  if (bad_n > 0) {
    throw Error("screened Poisson: " + std::to_string(bad_n) +
                " normal(s) with a non-finite component (first: row " + std::to_string(first_n) +
                ")");
  }
  if (zero_n > 0) {
    throw Error("screened Poisson: " + std::to_string(zero_n) +
                " zero-length normal(s) (first: row " + std::to_string(first_zero) +
                "); every point needs an orientation");
  }
  const double extent = box.Extent();
  if (!(extent > 0.0)) throw Error("screened Poisson: all points coincide");
  if (!std::isfinite(extent)) {
    throw Error("screened Poisson: the points' bounding box is too large (extent overflows)");
  }
  return box;
}

// Median distance to the nearest other point over a fixed subsample.
double MedianSpacing(const PointCloud& pc) {
  const Eigen::Index n = pc.P.rows();
  const Eigen::Index m = std::min<Eigen::Index>(n, 4096);
  KdTree3 tree(pc.P);
  std::vector<double> d;
  d.reserve(static_cast<std::size_t>(m));
  std::vector<double> sq;
  for (Eigen::Index k = 0; k < m; ++k) {
    const Eigen::Index i = k * n / m;  // evenly strided: deterministic, no RNG needed
    const std::vector<int> nb = tree.Knn(pc.P.row(i).transpose(), 2, &sq);
    // Skip exact duplicates: they say nothing about the spacing.
    for (std::size_t j = 0; j < nb.size(); ++j) {
      if (nb[j] != static_cast<int>(i) && sq[j] > 0.0) {
        d.push_back(std::sqrt(sq[j]));
        break;
      }
    }
  }
  if (d.empty()) return 0.0;
  auto mid = d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2);
  std::nth_element(d.begin(), mid, d.end());
  return *mid;
}

int AutoDepthFromBox(const PointCloud& pc, const PoissonOptions& o, const Box& box) {
  const double extent = box.Extent();
  double h = 2.0 * MedianSpacing(pc);
  // Only duplicates in the subsample: fall back to the spacing of n points
  // spread over a surface the size of the box.
  if (!(h > 0.0)) h = extent / std::sqrt(static_cast<double>(pc.P.rows()));
  const double cells = o.scale * extent / h;  // spacings across the octree's root cube
  const int d = static_cast<int>(std::lround(std::log2(std::max(cells, 1.0)))) + 1;
  return std::clamp(std::clamp(d, PoissonOptions::kMinAutoDepth, PoissonOptions::kMaxAutoDepth) + o.depth_offset, 2,
                    12);
}

// Puts the mesh in canonical order: vertices sorted lexicographically by
// position, each face rotated to start at its smallest index (keeping its
// winding), faces sorted. The output then does not depend on the order in
// which PCL's threads emitted it. On the way, vertices no face uses are
// dropped, vertices at exactly the same position are merged (PCL emits a few:
// 3 of 250k for a 100k-point sphere at depth 9, each with two zero-area faces)
// and the faces this collapses are removed. Returns {merged, removed faces}.
std::pair<int, int> CanonicalizeAndWeld(Mesh& m) {
  const Eigen::Index nv = m.V.rows(), nf = m.F.rows();
  std::vector<char> used(static_cast<std::size_t>(nv), 0);
  for (Eigen::Index f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) used[static_cast<std::size_t>(m.F(f, k))] = 1;
  std::vector<int> order;
  order.reserve(static_cast<std::size_t>(nv));
  for (Eigen::Index i = 0; i < nv; ++i)
    if (used[static_cast<std::size_t>(i)]) order.push_back(static_cast<int>(i));
  auto less = [&](int a, int b) {
    for (int k = 0; k < 3; ++k) {
      if (m.V(a, k) != m.V(b, k)) return m.V(a, k) < m.V(b, k);
    }
    return false;
  };
  std::sort(order.begin(), order.end(), less);
  std::vector<int> remap(static_cast<std::size_t>(nv), -1);
  std::vector<int> kept;  // old index of each new vertex
  int merged = 0;
  for (std::size_t i = 0; i < order.size(); ++i) {
    if (i > 0 && !less(order[i - 1], order[i])) {  // same position as the previous one
      remap[static_cast<std::size_t>(order[i])] = static_cast<int>(kept.size()) - 1;
      ++merged;
    } else {
      remap[static_cast<std::size_t>(order[i])] = static_cast<int>(kept.size());
      kept.push_back(order[i]);
    }
  }
  MatrixX3d V(static_cast<Eigen::Index>(kept.size()), 3);
  for (std::size_t i = 0; i < kept.size(); ++i) V.row(static_cast<Eigen::Index>(i)) = m.V.row(kept[i]);
  std::vector<std::array<int, 3>> faces;
  faces.reserve(static_cast<std::size_t>(nf));
  for (Eigen::Index f = 0; f < nf; ++f) {
    std::array<int, 3> t{remap[static_cast<std::size_t>(m.F(f, 0))],
                         remap[static_cast<std::size_t>(m.F(f, 1))],
                         remap[static_cast<std::size_t>(m.F(f, 2))]};
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
    faces.push_back(t);
  }
  const int removed = static_cast<int>(nf - static_cast<Eigen::Index>(faces.size()));
  m.V = std::move(V);
  m.F.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (int k = 0; k < 3; ++k) m.F(static_cast<Eigen::Index>(f), k) = faces[f][k];
  return {merged, removed};
}

// Rotates every face to start at its smallest index and sorts the faces.
void SortFaces(Mesh& m) {
  std::vector<std::array<int, 3>> faces(static_cast<std::size_t>(m.F.rows()));
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    std::array<int, 3> t{m.F(f, 0), m.F(f, 1), m.F(f, 2)};
    const auto r = std::min_element(t.begin(), t.end()) - t.begin();
    std::rotate(t.begin(), t.begin() + r, t.end());
    faces[static_cast<std::size_t>(f)] = t;
  }
  std::sort(faces.begin(), faces.end());
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (int k = 0; k < 3; ++k) m.F(static_cast<Eigen::Index>(f), k) = faces[f][k];
}

// PCL's adaptive marching cubes (PoissonRecon ~v5) occasionally leaves a
// crack: a small hole lying in the face between octree cells of different
// depths (seen: one 3-edge hole in 500k faces, sphere, 100k points, depth
// 9). Closes every boundary loop of at most `max_edges` edges with a fan,
// wound to match its neighbours; loops through a vertex with more than one
// outgoing boundary edge, and longer loops, are left alone. Returns
// {filled loops, boundary loops left open}.
std::pair<int, int> FillCracks(Mesh& m, int max_edges) {
  // Directed boundary edges: a->b used by a face while b->a is not.
  std::vector<std::pair<int, int>> half;
  half.reserve(static_cast<std::size_t>(3 * m.F.rows()));
  for (Eigen::Index f = 0; f < m.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) half.emplace_back(m.F(f, k), m.F(f, (k + 1) % 3));
  std::sort(half.begin(), half.end());
  std::vector<std::pair<int, int>> boundary;
  for (const auto& [a, b] : half) {
    if (!std::binary_search(half.begin(), half.end(), std::make_pair(b, a))) boundary.emplace_back(a, b);
  }
  if (boundary.empty()) return {0, 0};
  // boundary is sorted by source vertex; a vertex with two outgoing boundary
  // edges makes the loop ambiguous.
  std::vector<char> visited(boundary.size(), 0);
  auto next_of = [&](int v) -> std::ptrdiff_t {
    auto it = std::lower_bound(boundary.begin(), boundary.end(), std::make_pair(v, -1));
    if (it == boundary.end() || it->first != v) return -1;
    if (it + 1 != boundary.end() && (it + 1)->first == v) return -2;  // ambiguous
    return it - boundary.begin();
  };
  std::vector<std::array<int, 3>> added;
  int filled = 0, open = 0;
  for (std::size_t s = 0; s < boundary.size(); ++s) {
    if (visited[s]) continue;
    std::vector<int> loop;
    std::ptrdiff_t e = static_cast<std::ptrdiff_t>(s);
    bool ok = true;
    while (true) {
      visited[static_cast<std::size_t>(e)] = 1;
      loop.push_back(boundary[static_cast<std::size_t>(e)].first);
      const int to = boundary[static_cast<std::size_t>(e)].second;
      if (to == loop.front()) break;
      const std::ptrdiff_t nx = next_of(to);
      if (nx < 0 || visited[static_cast<std::size_t>(nx)] ||
          static_cast<int>(loop.size()) > max_edges) {
        ok = false;
        break;
      }
      e = nx;
    }
    if (!ok || static_cast<int>(loop.size()) < 3 || next_of(loop.front()) == -2) {
      ++open;
      continue;
    }
    // The loop follows the existing faces' boundary edges v_i -> v_{i+1};
    // the fan uses them reversed, so the orientation stays consistent.
    for (std::size_t i = 1; i + 1 < loop.size(); ++i) added.push_back({loop[0], loop[i + 1], loop[i]});
    ++filled;
  }
  if (!added.empty()) {
    const Eigen::Index nf = m.F.rows();
    m.F.conservativeResize(nf + static_cast<Eigen::Index>(added.size()), 3);
    for (std::size_t i = 0; i < added.size(); ++i)
      for (int k = 0; k < 3; ++k) m.F(nf + static_cast<Eigen::Index>(i), k) = added[i][k];
  }
  return {filled, open};
}

// Signed volume by the divergence theorem (> 0 for outward closed meshes).
double SignedVolume(const Mesh& m) {
  double v = 0.0;
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    const Vec3 a = m.V.row(m.F(f, 0)), b = m.V.row(m.F(f, 1)), c = m.V.row(m.F(f, 2));
    v += a.dot(b.cross(c));
  }
  return v / 6.0;
}

}  // namespace

int AutoPoissonDepth(const PointCloud& oriented, const PoissonOptions& options) {
  options.Check();
  const Box box = ValidateInput(oriented);
  return AutoDepthFromBox(oriented, options, box);
}

namespace {
// (occupied cells of side h) x h^2 / 1.5, points in cube units from `lo`.
double CellArea(const PointCloud& pc, const Vec3& lo, double cube, double h) {
  std::unordered_set<std::uint64_t> cells;
  cells.reserve(static_cast<std::size_t>(pc.P.rows()));
  for (Eigen::Index i = 0; i < pc.P.rows(); ++i) {
    const Vec3 q = (pc.P.row(i).transpose() - lo) / cube;
    std::uint64_t key = 0;
    for (int k = 0; k < 3; ++k) {
      const auto c = static_cast<std::uint64_t>(std::max(0.0, std::floor(q[k] / h)));
      key = key * 2097152u + std::min<std::uint64_t>(c, 2097151u);
    }
    cells.insert(key);
  }
  return static_cast<double>(cells.size()) * h * h;
}
}  // namespace

double EstimatePoissonSampleArea(const PointCloud& oriented, double scale, int depth) {
  const Box box = ValidateInput(oriented);
  if (!(scale > 0.0) || depth < 2) throw Error("EstimatePoissonSampleArea: needs scale > 0 and depth >= 2");
  const double cube = scale * box.Extent();
  // Cells too small leave gaps between the points (the count undershoots);
  // growing h, the estimate rises until the cells cover the surface, then
  // stays (until h nears the features). Start at PoissonRecon's kernel
  // depth (depth - 2) and double h until the estimate grows by < 10 %.
  double h = 1.0 / static_cast<double>(1 << std::max(0, depth - 2));
  double a = CellArea(oriented, box.lo, cube, h);
  for (int k = 0; k < 8 && 2.0 * h <= 0.25; ++k) {
    const double a2 = CellArea(oriented, box.lo, cube, 2.0 * h);
    h *= 2.0;
    if (a2 < 1.1 * a) {
      a = std::max(a, a2);
      break;
    }
    a = a2;
  }
  return a;
}

Mesh ReconstructPoisson(const PointCloud& oriented, const PoissonOptions& options,
                        const Context& ctx, double* used_weight, std::shared_ptr<void>* warm) {
  options.Check();
  const Box box = ValidateInput(oriented);
  ctx.CheckStop();
  const int depth = options.depth > 0 ? options.depth : AutoDepthFromBox(oriented, options, box);
  if (options.backend == PoissonOptions::Backend::kArcs) {
    SpsrOptions so;
    so.depth = depth;
    so.full_depth = std::max(1, std::min(options.min_depth, 8));
    so.scale = options.scale;
    so.samples_per_node = options.samples_per_node;
    so.point_weight = options.point_weight;
    so.iters = options.cg_iters;
    so.accuracy = options.cg_accuracy;
    so.base_accuracy = options.base_accuracy;
    so.fine_solver = options.fine_solver;
    so.gs_iters = options.gs_iters;
    so.extract_quantile = options.extract_quantile;
    so.extract_max_cell = options.extract_max_cell;
    so.normal_splat = options.normal_splat;
    so.density_scale = options.density_scale;
    so.iso_weight = options.iso_weight;
    so.screen_samples = options.screen_samples;
    so.carve = options.carve;
    so.carve_keep_voids = options.carve_keep_voids;
    std::shared_ptr<SpsrWarmStart> state;
    const bool use_warm = warm && options.warm_start;
    if (use_warm) state = std::static_pointer_cast<SpsrWarmStart>(*warm);
    SpsrInfo info;
    ctx.Info("screened Poisson (arcs): " + std::to_string(oriented.P.rows()) + " points, depth " +
             std::to_string(depth) + ", point weight " + std::to_string(options.point_weight));
    Mesh mesh = ReconstructSpsr(oriented, so, ctx, use_warm ? &state : nullptr, &info);
    if (use_warm) *warm = state;
    if (mesh.F.rows() == 0) {
      throw Error("screened Poisson (arcs): no surface (depth " + std::to_string(depth) + ", " +
                  std::to_string(oriented.P.rows()) + " points); the points may not bound a volume");
    }
    if (SignedVolume(mesh) < 0.0) {
      ctx.Info("screened Poisson: the normals point inward; flipping the output to outward");
      mesh.F.col(1).swap(mesh.F.col(2));
    }
    if (used_weight) *used_weight = options.point_weight;
    return mesh;
  }
  const bool open3d = options.backend == PoissonOptions::Backend::kOpen3d;
  if (!open3d && !PoissonAvailable()) throw Error("screened Poisson needs PCL: install libpcl-dev");
  if (open3d && !PoissonOpen3dAvailable())
    throw Error("screened Poisson (backend open3d): arcs was built without Open3D: install libopen3d-dev");

  // PCL works in single precision: hand it the points centred and scaled to
  // a unit box (in double), so far-from-origin or tiny clouds lose nothing;
  // the mesh is mapped back afterwards.
  const Vec3 center = box.Center();
  const double extent = box.Extent();
  const Eigen::Index n = oriented.P.rows();
  std::vector<float> xyz(static_cast<std::size_t>(3 * n)), nrm(static_cast<std::size_t>(3 * n));
  for (Eigen::Index i = 0; i < n; ++i) {
    const Vec3 q = (oriented.P.row(i).transpose() - center) / extent;
    // Scale by the largest component first: norm() of 1e-200 or 1e200
    // vectors under/overflows.
    Vec3 nn = oriented.N.row(i).transpose();
    nn = (nn / nn.cwiseAbs().maxCoeff()).normalized();
    for (int k = 0; k < 3; ++k) {
      xyz[static_cast<std::size_t>(3 * i + k)] = static_cast<float>(q[k]);
      nrm[static_cast<std::size_t>(3 * i + k)] = static_cast<float>(nn[k]);
    }
  }
  double weight = options.point_weight;
  // PCL's screening weight w acts per point as w * 2^d / N; PoissonRecon's
  // alpha as alpha * (estimated area / N) * 2^d, both in unit-cube units.
  const double pcl_per_unit = options.area_normalized && !open3d
                                  ? EstimatePoissonSampleArea(oriented, options.scale, depth)
                                  : 1.0;
  if (open3d && options.point_weight != 2.0) {
    ctx.Warn("screened Poisson (backend open3d): Open3D 0.16 fixes PoissonRecon's point weight at 2; point_weight " +
             std::to_string(options.point_weight) + " is ignored");
    weight = 2.0;
  }
  Mesh mesh;
  for (int attempt = 0;; ++attempt) {
    ctx.Info("screened Poisson: " + std::to_string(n) + " points, depth " + std::to_string(depth) +
             (options.depth == 0 ? " (automatic)" : "") + ", point weight " + std::to_string(weight));
    ctx.Progress(0.0, "screened Poisson");
    PoissonOptions o = options;
    o.point_weight = weight * pcl_per_unit;
    if (open3d) {
      std::vector<double> dx(xyz.begin(), xyz.end()), dn(nrm.begin(), nrm.end());
      mesh = poisson_detail::RunOpen3dPoisson(dx, dn, depth, options.scale, options.threads, false).mesh;
    } else {
      mesh = poisson_detail::RunPclPoisson(xyz, nrm, o, depth);
    }
    ctx.CheckStop();
    if (mesh.F.rows() == 0) {
      throw Error("screened Poisson: PCL produced no surface (depth " + std::to_string(depth) +
                  ", " + std::to_string(n) + " points); the points may not bound a volume");
    }
    for (Eigen::Index i = 0; i < mesh.V.rows(); ++i) {
      mesh.V.row(i) = (mesh.V.row(i) * extent + center.transpose()).eval();
    }
    const auto [merged, removed] = CanonicalizeAndWeld(mesh);
    const auto [filled, open] = FillCracks(mesh, kMaxCrackEdges);
    if (merged > 0 || removed > 0 || filled > 0) {
      ctx.Info("screened Poisson: merged " + std::to_string(merged) + " coincident vertices, removed " +
               std::to_string(removed) + " collapsed faces, closed " + std::to_string(filled) +
               " crack(s)");
    }
    if (open > 0 && attempt < options.open_retries && weight > 0.0 && !open3d) {
      // A strongly screened solve can leave sheets reaching the reconstruction
      // cube where the points are noisy (measured: fandisk n = 40 RFTA points,
      // open at weight 400, closed at 10); a weaker screening smooths them.
      ctx.Info("screened Poisson: the output is not closed (" + std::to_string(open) +
               " boundary loops) at point weight " + std::to_string(weight) + "; retrying at " +
               std::to_string(weight * options.retry_weight_factor));
      weight *= options.retry_weight_factor;
      continue;
    }
    if (open > 0) {
      // Typically the iso-surface reaching the reconstruction cube: points that
      // do not enclose a volume, inconsistent normals, or too few points.
      ctx.Warn("screened Poisson: the output is not closed: " + std::to_string(open) +
               " boundary loop(s) longer than " + std::to_string(kMaxCrackEdges) +
               " edges or not simple");
    } else if (SignedVolume(mesh) < 0.0) {
      // PCL winds faces consistently with the normals (outward for outward
      // normals); inward normals give the same surface wound inward. Closed
      // meshes in arcs have positive volume, so flip those.
      ctx.Info("screened Poisson: the normals point inward; flipping the output to outward");
      mesh.F.col(1).swap(mesh.F.col(2));
    }
    break;
  }
  if (used_weight) *used_weight = weight;
  SortFaces(mesh);
  ctx.Progress(1.0, "screened Poisson");
  return mesh;
}

}  // namespace arcs
