// morph: deform an icosphere so that its soft occupancy matches a target
// occupancy grid (Luo et al. §2.4; framework/voxel/morph.h).
#include "framework/voxel/morph.h"
#include "framework/voxel/voxelize.h"

#include "stages/builtin.h"

#include <Eigen/Core>

namespace arcs {

namespace {

// A cube grid of res³ nodes around the mesh's bounding box, 5 % margin on each
// side of the longest side (the surface never touches the grid's boundary).
GridInfo GridAround(const Mesh& m, int res) {
  const Vec3 lo = m.V.colwise().minCoeff().transpose(), hi = m.V.colwise().maxCoeff().transpose();
  const Vec3 c = 0.5 * (lo + hi);
  const double half = 0.55 * (hi - lo).maxCoeff();
  GridInfo g = CubeGrid(res, Vec3::Constant(0.0), Vec3::Constant(1.0));
  for (int a = 0; a < 3; ++a) {
    g.min[a] = c[a] - half;
    g.max[a] = c[a] + half;
  }
  return g;
}

}  // namespace

void RegisterMorphStages(Registry& r) {
  StageInfo s;
  s.name = "morph";
  s.role = Role::kOther;
  s.doc = "morph an icosphere to the target occupancy (a voxelizer's volume, else the reference's) "
          "by differentiable voxelization + Adam (Luo et al. §2.4)";
  const MorphOptions d;
  s.params.Int("res", 64, "grid nodes per axis when the reference is voxelized here (ignored with a volume)", 4, 512)
      .Int("subdivisions", 3, "icosphere subdivisions of the source (20*4^s faces)", 0, 7)
      .Int("iterations", d.iterations, "Adam steps", 0, 100000)
      .Double("lr", d.lr, "Adam learning rate (units of the grid's frame)", 1e-9, 1.0)
      .Double("smooth", d.smooth, "uniform-Laplacian energy weight", 0.0, 1e9)
      .Int("batch", d.batch, "grid nodes per step (0 = whole active set)", 0, 100000000)
      .Double("random_fraction", d.random_fraction, "share of the batch drawn uniformly from the grid", 0.0, 1.0)
      .Int("band", d.band, "active band half-width around both surfaces, voxels", 1, 64)
      .Int("refresh_every", d.refresh_every, "steps between active-set refreshes and IoU logs", 1, 100000)
      .Double("softening", d.softening_voxels, "softening of the eq. 4 kernel, voxels (0 = eq. 4 as printed)", 0.0, 100.0)
      .Choice("form", "naive", {"naive", "solid_angle"},
              "winding number of the loss: eq. 4 naive (paper's morphing) or Alg. 1 solid angle")
      .Choice("occupancy", "identity", {"identity", "clamp", "sigmoid"}, "occupancy from w (paper: identity)")
      .Double("sharpness", 10.0, "sigmoid sharpness (occupancy: sigmoid)", 1e-6, 1e6)
      .Choice("loss", "mse", {"mse", "bce"}, "per-node loss")
      .Choice("residual", "soft", {"soft", "exact"},
              "soft: gradient of the loss; exact: hard-occupancy residual through the form's gradient");
  s.factory = FunctionStage([](Context& ctx, CaseData& data, const ParamMap& p) {
    MorphOptions o;
    o.iterations = static_cast<int>(p.GetInt("iterations"));
    o.lr = p.GetDouble("lr");
    o.smooth = p.GetDouble("smooth");
    o.batch = static_cast<int>(p.GetInt("batch"));
    o.random_fraction = p.GetDouble("random_fraction");
    o.band = static_cast<int>(p.GetInt("band"));
    o.refresh_every = static_cast<int>(p.GetInt("refresh_every"));
    o.softening_voxels = p.GetDouble("softening");
    o.loss.occupancy.form = ParseWindingForm(p.GetString("form"));
    o.loss.occupancy.map = ParseOccupancyMap(p.GetString("occupancy"));
    o.loss.occupancy.sharpness = p.GetDouble("sharpness");
    o.loss.loss = ParseOccupancyLoss(p.GetString("loss"));
    o.residual = ParseMorphResidual(p.GetString("residual"));
    VolumeGrid target;
    if (data.volume) {
      target = *data.volume;
    } else {
      const Mesh& ref = data.RequireReference("morph");
      target.info = GridAround(ref, static_cast<int>(p.GetInt("res")));
      target.values = HardOccupancy(ref, target.info);
    }
    const Mesh src = InitialSphere(target, static_cast<int>(p.GetInt("subdivisions")));
    const MorphResult res = MorphToOccupancy(src, target, o, ctx, [&](const MorphLogEntry& e) {
      ctx.Info("morph: iteration " + std::to_string(e.iteration) + " IoU " + std::to_string(e.iou));
    });
    data.output = res.mesh;
    data.SetMetric("morph_iou", res.final_iou);
    data.SetMetric("morph_initial_iou", res.initial_iou);
    data.SetMetric("morph_iterations", res.iterations);
    data.SetMetric("morph_seconds", res.seconds);
    data.SetMetric("morph_grid_nodes", static_cast<double>(target.info.NumNodes()));
  });
  r.Register(std::move(s));
}

}  // namespace arcs
