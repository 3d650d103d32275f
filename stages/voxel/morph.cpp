// morph: deform an icosphere so that its soft occupancy matches a target
// occupancy grid (Luo et al. §2.4; framework/voxel/morph.h).
#include "framework/voxel/morph.h"
#include "framework/voxel/voxelize.h"

#include "stages/builtin.h"
#include "stages/voxel/voxel_params.h"

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

void RunMorph(Context& ctx, CaseData& data, const MorphStageOptions& o, const ParamMap&) {
  VolumeGrid target;
  if (data.volume) {
    target = *data.volume;
  } else {
    const Mesh& ref = data.RequireReference("morph");
    target.info = GridAround(ref, o.res);
    target.values = HardOccupancy(ref, target.info);
  }
  const Mesh src = InitialSphere(target, o.subdivisions);
  const MorphResult res = MorphToOccupancy(src, target, o.morph, ctx, [&](const MorphLogEntry& e) {
    ctx.Info("morph: iteration " + std::to_string(e.iteration) + " IoU " + std::to_string(e.iou));
  });
  data.output = res.mesh;
  data.SetMetric("morph_iou", res.final_iou);
  data.SetMetric("morph_initial_iou", res.initial_iou);
  data.SetMetric("morph_iterations", res.iterations);
  data.SetMetric("morph_seconds", res.seconds);
  data.SetMetric("morph_grid_nodes", static_cast<double>(target.info.NumNodes()));
}

}  // namespace

void RegisterMorphStages(Registry& r) {
  // The target is the volume if there is one, else the reference: neither
  // alone is a read, so the stage checks that one is there.
  StageInfo s = DeclareStage("morph", Role::kOther,
                             "morph an icosphere to the target occupancy (a voxelizer's volume, else the "
                             "reference's) by differentiable voxelization + Adam (Luo et al. §2.4)",
                             {}, {Slot::kOutput}, k3D);
  BindStage<MorphStageOptions>(s, MorphParams(), RunMorph);
  r.Register(std::move(s));
}

}  // namespace arcs
