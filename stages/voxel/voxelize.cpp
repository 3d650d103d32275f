// Voxelization stages (Luo et al.): `voxelize` (mesh -> occupancy volume),
// `volume_mc` (volume -> mesh, marching cubes at 0.5), `laplacian_smooth`
// (the paper's trimesh smoothing) and the `doph_metrics` evaluator (the
// paper's Chamfer / Hausdorff over 20 000 samples, 3 repeats).
#include "framework/voxel/doph_protocol.h"
#include "framework/voxel/voxelize.h"
#include "stages/builtin.h"
#include "stages/voxel/voxel_params.h"

#include <chrono>

namespace arcs {

namespace {

void RunVoxelize(Context& ctx, CaseData& d, const VoxelizeStageOptions& o, const ParamMap&) {
  const GridInfo g = CubeGrid(o.resolution, Vec3::Constant(o.lo), Vec3::Constant(o.hi));
  VoxelizeReport rep;
  const auto t0 = std::chrono::steady_clock::now();
  d.volume = Voxelize(*d.reference, g, o.voxelize, &rep);
  d.SetMetric("vox_seconds", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  d.SetMetric("vox_occupied", static_cast<double>(rep.occupied));
  d.SetMetric("vox_exact_evals", static_cast<double>(rep.exact_evaluations));
  d.SetMetric("vox_components", static_cast<double>(rep.components));
  d.SetMetric("vox_sheet_faces", static_cast<double>(rep.sheet_faces));
  if (rep.dropped_faces > 0) ctx.Warn("voxelize: dropped " + std::to_string(rep.dropped_faces) + " degenerate face(s)");
  ctx.Info("voxelize: path " + rep.path + ", " + std::to_string(rep.unbalanced_edges) + " unbalanced edge(s), " +
           std::to_string(rep.occupied) + " occupied node(s)");
}

void RegisterVoxelize(Registry& r) {
  StageInfo s = DeclareStage("voxelize", Role::kVoxelizer,
                             "winding-number occupancy of the reference mesh on an r^3 grid over [lo, hi]^3 (paper "
                             "Alg. 1; Alg. 2 / auto for open meshes)",
                             {Slot::kReference}, {Slot::kVolume}, k3D);
  BindStage<VoxelizeStageOptions>(s, VoxelizeParams(), RunVoxelize);
  r.Register(std::move(s));
}

void RunVolumeMc(Context&, CaseData& d, const ParamMap& p) {
  d.output = VolumeToMesh(*d.volume, p.GetDouble("level"));
  if (d.output->NumFaces() == 0) throw Error("the volume has no node above the level (empty output)");
}

void RegisterVolumeMc(Registry& r) {
  StageInfo s = DeclareStage("volume_mc", Role::kOther,
                             "marching cubes of the voxelizer's volume (inside = value > level), the paper's "
                             "re-meshing step",
                             {Slot::kVolume}, {Slot::kOutput}, k3D);
  s.params.Double("level", 0.5, "iso-value (paper: 0.5)");
  s.factory = FunctionStage(RunVolumeMc);
  r.Register(std::move(s));
}

Binder<LaplacianSmoothOptions> LaplacianSmoothParams() {
  using O = LaplacianSmoothOptions;
  return Binder<O>()
      .Int("iterations", &O::iterations, "smoothing iterations (paper: 10)", Closed(0, 100000))
      .Double("lambda", &O::lambda, "step size (paper: 0.15)", Closed(0.0, 1.0))
      .Bool("volume_constraint", &O::volume_constraint,
            "rescale about the origin to the initial volume after each step (trimesh default)");
}

void RunLaplacianSmooth(Context&, CaseData& d, const LaplacianSmoothOptions& o, const ParamMap&) {
  d.output = LaplacianSmooth(*d.output, o);
}

void RegisterLaplacianSmooth(Registry& r) {
  StageInfo s = DeclareStage("laplacian_smooth", Role::kOther,
                             "trimesh filter_laplacian on the output mesh: equal weights, explicit steps, volume "
                             "constraint (paper: 10 it., lambda 0.15)",
                             {Slot::kOutput}, {Slot::kOutput}, k3D);
  BindStage<LaplacianSmoothOptions>(s, LaplacianSmoothParams(), RunLaplacianSmooth);
  r.Register(std::move(s));
}

void RunDophMetrics(Context& ctx, CaseData& d, const ParamMap& p) {
  const DophMetrics m = ComputeDophMetrics(*d.output, *d.reference, p.GetInt("samples"),
                                           static_cast<int>(p.GetInt("repeats")), ctx.StreamSeed("doph_metrics"));
  d.SetMetric("doph_chamfer", m.chamfer);
  d.SetMetric("doph_chamfer_std", m.chamfer_std);
  d.SetMetric("doph_chamfer_sq", m.chamfer_sq);
  d.SetMetric("doph_chamfer_sq_std", m.chamfer_sq_std);
  d.SetMetric("doph_hausdorff", m.hausdorff);
  d.SetMetric("doph_hausdorff_std", m.hausdorff_std);
}

void RegisterDophMetrics(Registry& r) {
  StageInfo s = DeclareStage("doph_metrics", Role::kEvaluator,
                             "the voxelization paper's metrics: Chamfer mean(d1)+mean(d2), squared variant, "
                             "Hausdorff, over area-uniform samples, mean and std over repeats",
                             {Slot::kOutput, Slot::kReference}, {}, k3D);
  s.params.Int("samples", 20000, "area-uniform samples per mesh (paper: 20 000)", 1, 100000000)
      .Int("repeats", 3, "independent draws (paper: 3); *_std is their sample std", 1, 1000);
  s.outputs = {"doph_chamfer", "doph_chamfer_std", "doph_chamfer_sq", "doph_chamfer_sq_std", "doph_hausdorff",
               "doph_hausdorff_std"};
  s.factory = FunctionStage(RunDophMetrics);
  r.Register(std::move(s));
}

}  // namespace

void RegisterVoxelStages(Registry& r) {
  RegisterVoxelize(r);
  RegisterVolumeMc(r);
  RegisterLaplacianSmooth(r);
  RegisterDophMetrics(r);
}

}  // namespace arcs
