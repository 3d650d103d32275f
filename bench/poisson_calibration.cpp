// Calibration of the PCL back-end's area-normalised screening weight against
// PoissonRecon itself (Open3D 0.16's PoissonRecon 12, weight fixed at 2): the
// same oriented points at the official geometry (depth 10, cube 3.2x the
// cloud), PCL at point_weight 2 x k (area-normalised) for several k; prints
// the point-to-surface Chamfer between each PCL mesh and PoissonRecon's and
// their topology. k = 1 should be the closest if the normalisation is right.
//
//   poisson_calibration [POINTS.ply ...]   (default: noisy and sparse torus samples)
#include "framework/context.h"
#include "framework/eval/metrics.h"
#include "framework/geometry/builtin_shapes.h"
#include "framework/geometry/surface_sampling.h"
#include "framework/io/points_io.h"
#include "framework/reconstruct/poisson.h"
#include "framework/spatial/topology.h"
#include "framework/util/rng.h"

#include <Eigen/Geometry>

#include <cstdio>
#include <string>
#include <vector>

using namespace arcs;

namespace {

PointCloud TorusCloud(int n, double noise, std::uint64_t seed) {
  const Mesh t = MakeTorus();
  PointCloud pc;
  Eigen::VectorXi face;
  pc.P = SampleSurfaceUniform(t, n, seed, &face);
  pc.N.resize(n, 3);
  Rng rng(seed + 1);
  for (int i = 0; i < n; ++i) {
    const Vec3 a = t.V.row(t.F(face[i], 0)), b = t.V.row(t.F(face[i], 1)), c = t.V.row(t.F(face[i], 2));
    pc.N.row(i) = (b - a).cross(c - a).normalized();
    pc.P.row(i) += noise * Eigen::RowVector3d(rng.Normal(), rng.Normal(), rng.Normal());
  }
  return pc;
}

void Calibrate(const std::string& name, const PointCloud& pc) {
  PoissonOptions o;
  o.depth = 10;
  o.scale = 3.2;
  o.samples_per_node = 1.5;
  o.open_retries = 0;
  o.area_normalized = true;
  Context ctx(1);
  PoissonOptions po = o;
  po.backend = PoissonOptions::Backend::kOpen3d;
  po.point_weight = 2;
  const Mesh ref = ReconstructPoisson(pc, po, ctx);
  const Topology rt = ComputeTopology(ref);
  std::printf("%s: %d points, estimated area (cube units) %.4f; PoissonRecon 12 (weight 2): %d components, genus %d\n",
              name.c_str(), pc.Size(), EstimatePoissonSampleArea(pc, o.scale, o.depth), rt.components, rt.genus);
  std::printf("%8s %10s %12s %6s %6s\n", "k", "pcl_w", "p2s_vs_PR", "comp", "genus");
  for (double k : {0.125, 0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0}) {
    o.point_weight = 2.0 * k;
    const Mesh m = ReconstructPoisson(pc, o, ctx);
    const Topology t = ComputeTopology(m);
    std::printf("%8.3f %10.4f %12.6f %6d %6d\n", k, o.point_weight * EstimatePoissonSampleArea(pc, o.scale, o.depth),
                ChamferPointToSurface(m, ref, 100000, 1), t.components, t.genus);
    std::fflush(stdout);
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 1) {
    for (int i = 1; i < argc; ++i) Calibrate(argv[i], ReadPointCloud(argv[i]));
    return 0;
  }
  Calibrate("torus 5000, noise 0.01", TorusCloud(5000, 0.01, 5));
  Calibrate("torus 600, exact", TorusCloud(600, 0.0, 9));
  return 0;
}
