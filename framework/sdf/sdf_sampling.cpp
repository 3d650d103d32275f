#include "framework/sdf/sdf_sampling.h"

#include "framework/error.h"
#include "framework/spatial/triangle_bvh.h"
#include "framework/spatial/winding_number.h"
#include "framework/util/parallel.h"
#include "framework/util/rng.h"
#include "framework/voxel/doph_protocol.h"  // SignedVolume
#include "framework/voxel/voxelize.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <string>

namespace arcs {

void SdfGridOptions::Check() const {
  ARCS_CHECK_OPTION(n >= 1 && n <= kMaxN, "n", n, "an integer in [1, " + std::to_string(kMaxN) + "]");
  ARCS_CHECK_OPTION(std::isfinite(lo), "lo", lo, "finite");
  ARCS_CHECK_OPTION(std::isfinite(hi) && hi > lo, "hi", hi, "finite and greater than lo");
  ARCS_CHECK_OPTION(std::isfinite(fwn_beta) && fwn_beta > 0.0, "fwn_beta", fwn_beta,
                    "a finite number > 0");
}

VectorXd SignedDistance(const Mesh& mesh, const MatrixX3d& points, SdfSign sign,
                        double fwn_beta) {
  if (mesh.Empty()) throw Error("SignedDistance: the mesh is empty");
  VectorXd sq;
  const TriangleBvh bvh(mesh);
  bvh.ClosestPoints(points, &sq);
  VectorXd w;
  if (sign == SdfSign::kExactWindingNumber) {
    w = WindingNumbersExact(mesh, points);
  } else {
    FastWindingNumber::Options fo;
    fo.beta = fwn_beta;
    const FastWindingNumber fwn(mesh, fo);
    w = fwn.Eval(points);
  }
  VectorXd s(points.rows());
  for (Eigen::Index i = 0; i < s.size(); ++i) {
    const double d = std::sqrt(sq[i]);
    s[i] = w[i] > 0.5 ? -d : d;
  }
  return s;
}

namespace {

VoxelizeOptions SignVoxelizeOptions(SdfSign sign) {
  VoxelizeOptions vo;  // fast, occupancy, open_mesh auto, orientation abs
  if (sign == SdfSign::kExactWindingNumber) vo.method = "exact";
  return vo;
}

// Unsigned distances with the sign of `inside` (1 = inside: negative).
VectorXd Signed(const VectorXd& sq, const std::vector<std::uint8_t>& inside) {
  VectorXd s(sq.size());
  for (Eigen::Index i = 0; i < s.size(); ++i) {
    const double d = std::sqrt(sq[i]);
    s[i] = inside[static_cast<std::size_t>(i)] ? -d : d;
  }
  return s;
}

// The report's rule, counts and warnings; the warnings go to the log.
void FinishReport(const Mesh& mesh, const VoxelizeReport& vr, const VectorXd& s, const Context& ctx,
                  SdfSignReport* rep) {
  rep->rule = "voxelizer:" + vr.path;
  rep->unbalanced_edges = vr.unbalanced_edges;
  rep->shell_samples = vr.shell_nodes;
  rep->signed_volume = SignedVolume(mesh);
  rep->inside = (s.array() < 0.0).count();
  if (vr.unbalanced_edges > 0)
    rep->warnings.push_back("the mesh is not closed or not consistently oriented (" +
                            std::to_string(vr.unbalanced_edges) +
                            " unbalanced edges): SDF sign by the voxelizer's rule |w| > 1/2 plus a thin shell "
                            "around open sheets (" + std::to_string(vr.shell_nodes) + " samples by the shell)");
  else if (rep->signed_volume < 0.0)
    rep->warnings.push_back("the mesh is closed but faces inward (negative volume): SDF sign by |w| > 1/2");
  if (rep->inside == 0)
    rep->warnings.push_back("no sample is inside the mesh: the SDF is all positive");
  for (const auto& w : rep->warnings) ctx.Warn("sdf: " + w);
}

}  // namespace

SdfSamples SampleSdfGrid(const Mesh& mesh, const SdfGridOptions& options, const Context& ctx,
                         SdfSignReport* report) {
  options.Check();
  if (mesh.Empty()) throw Error("SampleSdfGrid: the mesh is empty");
  const int m = options.n + 1;
  GridInfo grid;
  grid.dim = 3;
  grid.dims = {m, m, m};
  grid.min = {options.lo, options.lo, options.lo};
  grid.max = {options.hi, options.hi, options.hi};
  // linspace(lo, hi, n+1): lo + i*h, with the last node exactly hi.
  std::vector<double> c(m);
  const double h = (options.hi - options.lo) / options.n;
  for (int i = 0; i < m; ++i) c[i] = options.lo + i * h;
  c.back() = options.hi;

  const std::int64_t total = grid.NumNodes();
  SdfSamples out;
  out.dim = 3;
  out.points.resize(total, 3);
  ParallelFor(total, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t idx = b; idx < e; ++idx) {
      const std::int64_t i = idx % m, j = (idx / m) % m, k = idx / (static_cast<std::int64_t>(m) * m);
      out.points(idx, 0) = c[i];
      out.points(idx, 1) = c[j];
      out.points(idx, 2) = c[k];
    }
  }, 1 << 14);
  ctx.CheckStop();
  const MatrixX3d P = out.points;  // MatrixXd (dynamic columns) -> N x 3
  SdfSignReport local;
  SdfSignReport* rep = report ? report : &local;
  *rep = SdfSignReport{};
  if (options.inside == SdfInside::kWinding) {
    out.values = SignedDistance(mesh, P, options.sign, options.fwn_beta);
    rep->rule = "winding";
    rep->inside = (out.values.array() < 0.0).count();
  } else {
    // The voxelizer's occupancy of this very grid: node for node the same
    // inside as `arcs voxelize` (GridCoord is the same linspace).
    VectorXd sq;
    TriangleBvh(mesh).ClosestPoints(P, &sq);
    ctx.CheckStop();
    VoxelizeOptions vo = SignVoxelizeOptions(options.sign);
    vo.beta = options.fwn_beta;
    VoxelizeReport vr;
    const VolumeGrid occ = Voxelize(mesh, grid, vo, &vr);
    std::vector<std::uint8_t> in(static_cast<std::size_t>(total));
    for (std::int64_t i = 0; i < total; ++i) in[static_cast<std::size_t>(i)] = occ.values[i] > 0.5;
    out.values = Signed(sq, in);
    FinishReport(mesh, vr, out.values, ctx, rep);
  }
  out.grid = grid;
  return out;
}

SdfSamples SampleSdfRandom(const Mesh& mesh, std::int64_t count, double lo, double hi,
                           const Context& ctx, SdfSign sign, SdfInside inside, SdfSignReport* report) {
  if (count < 0) throw Error("SampleSdfRandom: count = " + std::to_string(count) + " < 0");
  if (!(std::isfinite(lo) && std::isfinite(hi) && hi > lo)) {
    throw Error("SampleSdfRandom: the box [lo, hi] must be finite with hi > lo");
  }
  if (mesh.Empty()) throw Error("SampleSdfRandom: the mesh is empty");
  const std::uint64_t seed = ctx.StreamSeed("sdf_random");
  MatrixX3d P(count, 3);
  ParallelFor(count, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t i = b; i < e; ++i) {
      Rng rng(HashSeed(seed, static_cast<std::uint64_t>(i)));
      for (int a = 0; a < 3; ++a) P(i, a) = rng.Uniform(lo, hi);
    }
  }, 4096);
  ctx.CheckStop();
  SdfSamples out;
  out.dim = 3;
  SdfSignReport local;
  SdfSignReport* rep = report ? report : &local;
  *rep = SdfSignReport{};
  if (inside == SdfInside::kWinding) {
    out.values = SignedDistance(mesh, P, sign);
    rep->rule = "winding";
    rep->inside = (out.values.array() < 0.0).count();
  } else {
    VectorXd sq;
    TriangleBvh(mesh).ClosestPoints(P, &sq);
    ctx.CheckStop();
    // The open-mesh shell's spacing: that of a grid with as many nodes.
    const double per_axis = std::max(2.0, std::cbrt(static_cast<double>(std::max<std::int64_t>(count, 8))));
    const double h = (hi - lo) / (per_axis - 1.0);
    VoxelizeReport vr;
    const std::vector<std::uint8_t> in = OccupancyAtPoints(mesh, P, h, SignVoxelizeOptions(sign), &vr);
    out.values = Signed(sq, in);
    FinishReport(mesh, vr, out.values, ctx, rep);
  }
  out.points = P;
  return out;
}

void SdfRandomOptions::Check() const {
  ARCS_CHECK_OPTION(count >= 1 && count <= 1000000000, "count", count, "an integer in [1, 1e9]");
  ARCS_CHECK_OPTION(std::isfinite(lo), "lo", lo, "finite");
  ARCS_CHECK_OPTION(std::isfinite(hi) && hi > lo, "hi", hi, "finite and greater than lo");
}

SdfSamples SampleSdfRandom(const Mesh& mesh, const SdfRandomOptions& o, const Context& ctx,
                           SdfSignReport* report) {
  o.Check();
  return SampleSdfRandom(mesh, o.count, o.lo, o.hi, ctx, o.sign, o.inside, report);
}

void SdfNoiseOptions::Check() const {
  ARCS_CHECK_OPTION(std::isfinite(sigma) && sigma >= 0.0, "sigma", sigma, "a finite number >= 0");
}

void SdfClampOptions::Check() const {
  ARCS_CHECK_OPTION(std::isfinite(clamp) && clamp > 0.0, "clamp", clamp, "a finite number > 0");
}

void AddGaussianNoise(SdfSamples* samples, double sigma, std::uint64_t seed) {
  SdfNoiseOptions{sigma}.Check();
  if (sigma == 0.0) return;
  VectorXd& v = samples->values;
  ParallelFor(v.size(), [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t i = b; i < e; ++i) {
      Rng rng(HashSeed(seed, static_cast<std::uint64_t>(i)));
      v[i] += sigma * rng.Normal();
    }
  }, 4096);
}

void ClampSdf(SdfSamples* samples, double clamp) {
  SdfClampOptions{clamp}.Check();
  for (Eigen::Index i = 0; i < samples->values.size(); ++i) {
    samples->values[i] = std::clamp(samples->values[i], -clamp, clamp);
  }
  // Clamping an already clamped SDF keeps the tighter bound.
  samples->clamp = samples->clamp > 0.0 ? std::min(samples->clamp, clamp) : clamp;
}

}  // namespace arcs
