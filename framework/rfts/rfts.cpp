// Reach for the Spheres: the sphere flow (see rfts.h for the steps).
#include "framework/rfts/rfts.h"

#include "framework/error.h"
#include "framework/geometry/builtin_shapes.h"
#include "framework/rfta/sphere_set.h"
#include "framework/rfts/remesh.h"
#include "framework/spatial/knn.h"
#include "framework/spatial/topology.h"
#include "framework/spatial/triangle_bvh.h"

#include <Eigen/Geometry>
#include "framework/util/parallel.h"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>

namespace arcs {

void RftsOptions::Check() const {
  // Hard limits of the algorithm and sane caps (the rfts stage declares the
  // same bounds; tests/registry/bounds_agree_test.cpp checks they agree).
  ARCS_CHECK_OPTION(max_iterations >= 0 && max_iterations <= 100000000, "max_iterations", max_iterations,
                    "in [0, 1e8]");
  ARCS_CHECK_OPTION(tol > 0 && tol <= 1.0, "tol", tol, "in (0, 1]");
  ARCS_CHECK_OPTION(initial_edge_length > 0 && initial_edge_length <= 10.0, "initial_edge_length",
                    initial_edge_length, "in (0, 10]");
  // min_edge_length >= initial_edge_length: h is never halved.
  ARCS_CHECK_OPTION(min_edge_length >= 0 && min_edge_length <= 10.0, "min_edge_length", min_edge_length,
                    "0 (heuristic) or in (0, 10]");
  // min_step <= 1 <= max_step, so the clamp of t is never empty.
  ARCS_CHECK_OPTION(min_step > 0 && min_step <= 1.0, "min_step", min_step, "in (0, 1]");
  ARCS_CHECK_OPTION(max_step >= 1.0 && max_step <= 1e6, "max_step", max_step, "in [1, 1e6]");
  ARCS_CHECK_OPTION(fixed_step > 0 && fixed_step <= 1e6, "fixed_step", fixed_step, "in (0, 1e6]");
  ARCS_CHECK_OPTION(batch_size >= 0 && batch_size <= 1000000000, "batch_size", batch_size,
                    "in [0, 1e9] (0 = all samples)");
  ARCS_CHECK_OPTION(remesh_iterations >= 0 && remesh_iterations <= 100, "remesh_iterations", remesh_iterations,
                    "in [0, 100]");
  // collapse_ratio <= 1 < split_ratio: the remesher's two thresholds never cross.
  ARCS_CHECK_OPTION(split_ratio > 1 && split_ratio <= 10.0, "split_ratio", split_ratio, "in (1, 10]");
  ARCS_CHECK_OPTION(collapse_ratio > 0 && collapse_ratio <= 1.0, "collapse_ratio", collapse_ratio, "in (0, 1]");
  ARCS_CHECK_OPTION(patience >= 1 && patience <= 1000000, "patience", patience, "in [1, 1e6]");
  // max_stall < patience: the flow stops before h is ever halved.
  ARCS_CHECK_OPTION(max_stall >= 1 && max_stall <= 100000000, "max_stall", max_stall, "in [1, 1e8]");
  ARCS_CHECK_OPTION(barycentric_threshold >= 0 && barycentric_threshold < 1.0 / 3.0, "barycentric_threshold",
                    barycentric_threshold, "in [0, 1/3)");
  ARCS_CHECK_OPTION(initial_subdivisions >= 0 && initial_subdivisions <= 7, "initial_subdivisions",
                    initial_subdivisions, "in [0, 7]");
  ARCS_CHECK_OPTION(max_area_ratio > 0 && max_area_ratio <= 1e9, "max_area_ratio", max_area_ratio, "in (0, 1e9]");
  ARCS_CHECK_OPTION(initial_radius > 0 && initial_radius <= 100.0, "initial_radius", initial_radius,
                    "in (0, 100]");
}

VectorXd VoronoiMass(const Mesh& m) {
  VectorXd mass = VectorXd::Zero(m.NumVertices());
  for (int f = 0; f < m.NumFaces(); ++f) {
    const int id[3] = {m.F(f, 0), m.F(f, 1), m.F(f, 2)};
    Vec3 p[3];
    for (int k = 0; k < 3; ++k) p[k] = m.V.row(id[k]).transpose();
    const double area = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).norm();
    if (!(area > 0)) continue;
    // cot of the angle at corner k, and whether it is obtuse.
    double cot[3];
    int obtuse = -1;
    for (int k = 0; k < 3; ++k) {
      const Vec3 a = p[(k + 1) % 3] - p[k], b = p[(k + 2) % 3] - p[k];
      cot[k] = a.dot(b) / (2.0 * area);
      if (a.dot(b) < 0) obtuse = k;
    }
    for (int k = 0; k < 3; ++k) {
      double share;
      if (obtuse < 0) {
        // Voronoi region of corner k: (|e_kj|² cot(l) + |e_kl|² cot(j)) / 8.
        const int j = (k + 1) % 3, l = (k + 2) % 3;
        share = ((p[j] - p[k]).squaredNorm() * cot[l] + (p[l] - p[k]).squaredNorm() * cot[j]) / 8.0;
      } else {
        share = obtuse == k ? area / 2 : area / 4;
      }
      mass[id[k]] += share;
    }
  }
  return mass;
}

namespace {

using Clock = std::chrono::steady_clock;
double Since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Barycentric coordinates of p (a point of triangle abc) w.r.t. a, b, c.
Vec3 Barycentric(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 v0 = b - a, v1 = c - a, v2 = p - a;
  const double d00 = v0.dot(v0), d01 = v0.dot(v1), d11 = v1.dot(v1);
  const double d20 = v2.dot(v0), d21 = v2.dot(v1);
  const double den = d00 * d11 - d01 * d01;
  if (!(std::abs(den) > 1e-30 * (d00 * d11 + 1e-300))) {
    // Degenerate face: weight the nearest corner.
    const double da = (p - a).squaredNorm(), db = (p - b).squaredNorm(), dc = (p - c).squaredNorm();
    if (da <= db && da <= dc) return Vec3(1, 0, 0);
    return db <= dc ? Vec3(0, 1, 0) : Vec3(0, 0, 1);
  }
  double v = (d11 * d20 - d01 * d21) / den;
  double w = (d00 * d21 - d01 * d20) / den;
  Vec3 bary(1 - v - w, v, w);
  bary = bary.cwiseMax(0.0);
  return bary / bary.sum();
}

double Sign(double x) { return x > 0 ? 1.0 : (x < 0 ? -1.0 : 0.0); }

// Why a mesh is not a valid state of the flow (empty = fine). `max_area`
// and `max_coord` catch a diverging flow (working frame).
std::string Singularity(const Mesh& m, double max_area, double max_coord) {
  for (int v = 0; v < m.NumVertices(); ++v) {
    if (!m.V.row(v).allFinite()) return "non-finite vertex " + std::to_string(v);
    if (m.V.row(v).cwiseAbs().maxCoeff() > max_coord)
      return "vertex " + std::to_string(v) + " left the sample box (diverging flow)";
  }
  double area = 0;
  for (int f = 0; f < m.NumFaces(); ++f) {
    const Vec3 a = m.V.row(m.F(f, 0)), b = m.V.row(m.F(f, 1)), c = m.V.row(m.F(f, 2));
    const double a2 = (b - a).cross(c - a).norm();
    if (!(a2 > 1e-12)) return "zero-area face " + std::to_string(f);
    area += a2 / 2;
  }
  if (area > max_area)
    return "mesh area " + std::to_string(area) + " above " + std::to_string(max_area) + " (folding, diverging flow)";
  const Topology t = ComputeTopology(m);
  if (t.nonmanifold_edges > 0) return std::to_string(t.nonmanifold_edges) + " non-manifold edges";
  return {};
}

}  // namespace

RftsResult ReachForTheSpheres(const SdfSamples& samples, const RftsOptions& o, const Context& ctx) {
  o.Check();
  CheckRftaSamples(samples, "rfts");
  if (samples.dim != 3)
    throw Error("rfts: needs 3D SDF samples (got dim = " + std::to_string(samples.dim) + ")");
  const std::int64_t n = samples.Size();
  if (!(samples.values.minCoeff() < 0))
    throw Error("rfts: no SDF sample is negative (inside): all " + std::to_string(n) +
                " samples are outside the shape, there is no surface to reach");
  if (!(samples.values.maxCoeff() > 0))
    throw Error("rfts: no SDF sample is positive (outside): all " + std::to_string(n) +
                " samples are inside or on the shape, there is no surface to reach");

  // Working frame: bounding-box centre, half the largest extent.
  Vec3 lo = samples.points.leftCols(3).colwise().minCoeff().transpose();
  Vec3 hi = samples.points.leftCols(3).colwise().maxCoeff().transpose();
  const Vec3 centre = 0.5 * (lo + hi);
  const double scale = 0.5 * (hi - lo).maxCoeff();
  MatrixX3d U(n, 3);
  for (std::int64_t i = 0; i < n; ++i) U.row(i) = (samples.points.row(i).leftCols(3) - centre.transpose()) / scale;
  const VectorXd S = samples.values / scale;
  const double clamp = samples.clamp > 0 ? samples.clamp / scale : 0.0;

  RftsResult res;
  // min_h: clip(2 · mean nearest-neighbour distance, 0.001, 0.1) (official).
  double min_h = o.min_edge_length;
  if (min_h == 0) {
    KdTree3 tree(U);
    Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> knn;
    tree.KnnBatch(U, 2, &knn);
    double sum = 0;
    for (std::int64_t i = 0; i < n; ++i) {
      const int j = knn(i, 1) >= 0 && knn(i, 1) != i ? knn(i, 1) : knn(i, 0);
      sum += (U.row(i) - U.row(j)).norm();
    }
    min_h = std::clamp(2.0 * sum / n, 0.001, 0.1);
    min_h = std::min(min_h, o.initial_edge_length);
  }
  res.min_edge_length = min_h;

  // Divergence guards (ours; the flow on genus > 0 folds the mesh through
  // itself and, with a remesher that never makes a degenerate face, would grow
  // without bound instead of stopping): a vertex far outside the sample box,
  // or more area than max_area_ratio times the box's surface.
  const Vec3 ext = (hi - lo) / scale;  // box extents in the working frame (largest = 2)
  const double max_area = o.max_area_ratio * 2 * (ext.x() * ext.y() + ext.y() * ext.z() + ext.z() * ext.x());
  const double max_coord = 2.0 * std::max(1.0, o.initial_radius);
  Mesh cur = MakeIcosphere(o.initial_radius, o.initial_subdivisions);
  Mesh last_converged = cur;
  double h = o.initial_edge_length;
  double best = std::numeric_limits<double>::infinity();
  int counter = 0;
  Rng rng = ctx.MakeRng("rfts");
  std::vector<int> perm(n);
  std::iota(perm.begin(), perm.end(), 0);
  std::vector<char> chosen(n, 0);
  const bool all = o.batch_size == 0 || o.batch_size >= n;
  RemeshOptions ro;
  ro.split_ratio = o.split_ratio;
  ro.collapse_ratio = o.collapse_ratio;
  ro.iterations = o.remesh_iterations;
  res.stop_reason = "max_iterations";

  for (int it = 0; it < o.max_iterations; ++it) {
    ctx.CheckStop();
    // (1) The batch.
    std::vector<int> batch;
    if (all) {
      batch = perm;
    } else {
      for (std::int64_t i = 0; i < o.batch_size; ++i) {
        const std::int64_t j = i + static_cast<std::int64_t>(rng.UniformInt(n - i));
        std::swap(perm[i], perm[j]);
      }
      std::fill(chosen.begin(), chosen.end(), 0);
      for (std::int64_t i = 0; i < o.batch_size; ++i) chosen[perm[i]] = 1;
      for (std::int64_t i = 0; i < n; ++i)
        if (chosen[i] || S[i] <= 0) batch.push_back(static_cast<int>(i));
    }
    const int nb = static_cast<int>(batch.size());
    // (2) Closest points.
    auto t0 = Clock::now();
    MatrixX3d Q(nb, 3);
    for (int i = 0; i < nb; ++i) Q.row(i) = U.row(batch[i]);
    VectorXd d2;
    MatrixX3d P;
    Eigen::VectorXi I;
    TriangleBvh(cur).ClosestPoints(Q, &d2, &P, &I);
    // (3)-(6) Sides, targets, validity, the rows of A.
    const int nv = cur.NumVertices(), nf = cur.NumFaces();
    std::vector<char> active(nf, 0);
    std::vector<Eigen::Triplet<double>> trip;
    trip.reserve(3 * nb);
    MatrixXd C(nb, 3);
    std::int64_t invalid = 0;
    for (int i = 0; i < nb; ++i) {
      const double s = S[batch[i]];
      const Vec3 u = Q.row(i).transpose(), p = P.row(i).transpose();
      const int f = I[i];
      const Vec3 a = cur.V.row(cur.F(f, 0)), b = cur.V.row(cur.F(f, 1)), c = cur.V.row(cur.F(f, 2));
      const Vec3 bary = Barycentric(p, a, b, c);
      const Vec3 w = p - u;
      const double d = std::sqrt(d2[i]);
      double sigma = -Sign(w.dot((b - a).cross(c - a)));
      if (bary.minCoeff() < o.barycentric_threshold) sigma = Sign(s);
      const Vec3 target = u + w * (sigma * s / std::max(o.tol / 2, d));
      const double g = std::abs(s) - d;
      if (!(std::abs(g) < o.tol)) {
        ++invalid;
        active[f] = 1;
      }
      const double weight = (clamp > 0 && std::abs(s) >= clamp * (1 - 1e-12) && g < 0) ? 0.0 : 1.0;
      for (int k = 0; k < 3; ++k)
        if (weight * bary[k] != 0) trip.emplace_back(i, cur.F(f, k), weight * bary[k]);
      C.row(i) = weight * target.transpose();
    }
    res.query_s += Since(t0);
    res.final_invalid = invalid;
    res.iterations = it;
    t0 = Clock::now();
    Eigen::SparseMatrix<double> A(nb, nv);
    A.setFromTriplets(trip.begin(), trip.end());
    const MatrixXd V = cur.V;
    // (7) Step size.
    double t = o.fixed_step;
    if (o.line_search) {
      const MatrixXd r = A * V - C;
      const MatrixXd np = -(A.transpose() * r) / nb;
      const MatrixXd Anp = A * np;
      t = -((r.cwiseProduct(Anp)).sum() / nb + 0.01 * np.squaredNorm()) / (Anp.squaredNorm() / nb);
      if (!std::isfinite(t)) t = 0;
      t = std::clamp(t, o.min_step, o.max_step);
    }
    // (8) Implicit step (M + t AᵀRA) V' = M V + t AᵀR c.
    const VectorXd mass = VoronoiMass(cur);
    Eigen::SparseMatrix<double> K = (A.transpose() * A) * (t / nb);
    for (int v = 0; v < nv; ++v) K.coeffRef(v, v) += mass[v];
    const MatrixXd rhs = mass.asDiagonal() * V + (A.transpose() * C) * (t / nb);
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(K);
    std::string why;
    if (ldlt.info() != Eigen::Success) {
      why = "the implicit step's matrix could not be factorised";
    } else {
      const MatrixXd Vn = ldlt.solve(rhs);
      if (ldlt.info() != Eigen::Success) why = "the implicit step's solve failed";
      else cur.V = Vn;
    }
    res.solve_s += Since(t0);
    // (9) Singularity guard.
    if (why.empty()) why = Singularity(cur, max_area, max_coord);
    if (!why.empty()) {
      res.singular = true;
      res.stop_reason = "singularity: " + why + " at iteration " + std::to_string(it);
      cur = last_converged;
      break;
    }
    // (10) Convergence bookkeeping in the source's order (rfts.h): the error
    // of the moved mesh; nothing is saved at min_h, so a flow that diverges
    // there and hits a guard returns the mesh it reached min_h with.
    const double err = (A * cur.V - C).norm() / nb;
    res.final_error = err;
    if (err < best - 1e-3 * o.tol) {
      best = err;
      counter = 0;
    } else {
      ++counter;
    }
    if (counter > o.patience) {
      if (h > min_h) {
        last_converged = cur;
        best = std::numeric_limits<double>::infinity();
        counter = 0;
        ++res.halvings;
      }
      h = std::max(h / 2, min_h);
    }
    if (invalid == 0 || counter > o.max_stall) {
      res.stop_reason = invalid == 0 ? "converged" : "stalled";
      res.iterations = it + 1;
      break;
    }
    // (11) Remesh the active faces grown twice by one-rings.
    t0 = Clock::now();
    for (int grow = 0; grow < 2; ++grow) {
      std::vector<char> vmark(nv, 0);
      for (int f = 0; f < nf; ++f)
        if (active[f])
          for (int k = 0; k < 3; ++k) vmark[cur.F(f, k)] = 1;
      for (int f = 0; f < nf; ++f)
        if (vmark[cur.F(f, 0)] || vmark[cur.F(f, 1)] || vmark[cur.F(f, 2)]) active[f] = 1;
    }
    ro.target_edge_length = h;
    const bool whole = std::all_of(active.begin(), active.end(), [](char c) { return c != 0; });
    try {
      RemeshPatch(&cur, whole ? std::vector<char>{} : active, ro);
      why = Singularity(cur, max_area, max_coord);
    } catch (const Error& e) {
      why = std::string("remeshing failed: ") + e.what();
    }
    res.remesh_s += Since(t0);
    if (!why.empty()) {
      res.singular = true;
      res.stop_reason = "singularity: " + why + " after remeshing at iteration " + std::to_string(it);
      cur = last_converged;
      break;
    }
    res.iterations = it + 1;
    if ((it & 63) == 0) ctx.Progress(static_cast<double>(it) / std::max(1, o.max_iterations), "rfts flow");
  }
  res.final_edge_length = h;
  res.mesh.F = cur.F;
  res.mesh.V.resize(cur.NumVertices(), 3);
  for (int v = 0; v < cur.NumVertices(); ++v) res.mesh.V.row(v) = cur.V.row(v) * scale + centre.transpose();
  return res;
}

}  // namespace arcs
