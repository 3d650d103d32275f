// The paper's evaluation protocol; see doph_protocol.h.
#include "framework/voxel/doph_protocol.h"

#include "framework/error.h"
#include "framework/geometry/marching_cubes.h"
#include "framework/geometry/surface_sampling.h"
#include "framework/spatial/knn.h"
#include "framework/util/rng.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <vector>

namespace arcs {

Mesh VolumeToMesh(const VolumeGrid& volume, double level) {
  if (volume.values.size() != volume.info.NumNodes())
    throw Error("VolumeToMesh: the volume has " + std::to_string(volume.values.size()) + " values for " +
                std::to_string(volume.info.NumNodes()) + " grid nodes");
  // MarchingCubes: inside iff value < iso; negate so that inside = value > level.
  const VectorXd neg = -volume.values;
  return MarchingCubes(neg, volume.info, -level);
}

void LaplacianSmoothOptions::Check() const {
  ARCS_CHECK_OPTION(iterations >= 0 && iterations <= 100000, "iterations", iterations, "an integer in [0, 100000]");
  ARCS_CHECK_OPTION(std::isfinite(lambda) && lambda >= 0.0 && lambda <= 1.0, "lambda", lambda, "a number in [0, 1]");
}

double SignedVolume(const Mesh& m) {
  double v = 0.0;
  for (int f = 0; f < m.NumFaces(); ++f) {
    const Vec3 a = m.V.row(m.F(f, 0)), b = m.V.row(m.F(f, 1)), c = m.V.row(m.F(f, 2));
    v += a.dot(b.cross(c));
  }
  return v / 6.0;
}

Mesh LaplacianSmooth(const Mesh& mesh, const LaplacianSmoothOptions& o) {
  o.Check();
  Mesh out = mesh;
  const int nv = mesh.NumVertices();
  // Unique edge neighbours per vertex (trimesh's vertex_neighbors).
  std::vector<std::vector<int>> nb(nv);
  for (int f = 0; f < mesh.NumFaces(); ++f)
    for (int c = 0; c < 3; ++c) {
      const int a = mesh.F(f, c), b = mesh.F(f, (c + 1) % 3);
      if (a == b) continue;
      nb[a].push_back(b);
      nb[b].push_back(a);
    }
  for (auto& n : nb) {
    std::sort(n.begin(), n.end());
    n.erase(std::unique(n.begin(), n.end()), n.end());
  }
  const double v0 = SignedVolume(mesh);
  MatrixX3d next(nv, 3);
  for (int it = 0; it < o.iterations; ++it) {
    for (int v = 0; v < nv; ++v) {
      if (nb[v].empty()) {
        next.row(v) = out.V.row(v);
        continue;
      }
      Eigen::RowVector3d s = Eigen::RowVector3d::Zero();
      for (int u : nb[v]) s += out.V.row(u);
      s /= static_cast<double>(nb[v].size());
      next.row(v) = out.V.row(v) + o.lambda * (s - out.V.row(v));
    }
    out.V.swap(next);
    if (o.volume_constraint) {
      const double ratio = v0 / SignedVolume(out);
      if (std::isfinite(ratio) && ratio > 0.0) out.V *= std::cbrt(ratio);
    }
  }
  return out;
}

DophMetrics ComputeDophMetrics(const Mesh& output, const Mesh& reference, std::int64_t samples, int repeats,
                               std::uint64_t seed) {
  if (output.NumFaces() == 0) throw Error("doph metrics: the output mesh is empty");
  if (reference.NumFaces() == 0) throw Error("doph metrics: the reference mesh is empty");
  if (samples < 1 || repeats < 1) throw OptionError("doph metrics: samples and repeats must be >= 1");
  std::vector<double> ch, chsq, hd;
  for (int r = 0; r < repeats; ++r) {
    const std::uint64_t s = HashSeed(seed, static_cast<std::uint64_t>(r));
    const MatrixX3d A = SampleSurfaceUniform(output, samples, HashSeed(s, 1));
    const MatrixX3d B = SampleSurfaceUniform(reference, samples, HashSeed(s, 2));
    Eigen::VectorXi idx;
    VectorXd d1, d2;
    KdTree3(B).NearestBatch(A, &idx, &d1);
    KdTree3(A).NearestBatch(B, &idx, &d2);
    const double m1 = d1.cwiseSqrt().mean(), m2 = d2.cwiseSqrt().mean();
    ch.push_back(m1 + m2);
    chsq.push_back(d1.mean() + d2.mean());
    hd.push_back(std::sqrt(std::max(d1.maxCoeff(), d2.maxCoeff())));
  }
  auto mean_std = [](const std::vector<double>& v, double* m, double* sd) {
    double s = 0;
    for (double x : v) s += x;
    *m = s / v.size();
    double q = 0;
    for (double x : v) q += (x - *m) * (x - *m);
    *sd = v.size() > 1 ? std::sqrt(q / (v.size() - 1)) : 0.0;
  };
  DophMetrics d;
  mean_std(ch, &d.chamfer, &d.chamfer_std);
  mean_std(chsq, &d.chamfer_sq, &d.chamfer_sq_std);
  mean_std(hd, &d.hausdorff, &d.hausdorff_std);
  return d;
}

}  // namespace arcs
