// Voxelization stages (Luo et al.): `voxelize` (mesh -> occupancy volume),
// `volume_mc` (volume -> mesh, marching cubes at 0.5), `laplacian_smooth`
// (the paper's trimesh smoothing) and the `doph_metrics` evaluator (the
// paper's Chamfer / Hausdorff over 20 000 samples, 3 repeats).
#include "framework/voxel/doph_protocol.h"
#include "framework/voxel/voxelize.h"
#include "stages/builtin.h"

#include <chrono>

namespace arcs {

namespace {

void RegisterVoxelize(Registry& r) {
  StageInfo s;
  s.name = "voxelize";
  s.role = Role::kVoxelizer;
  s.doc = "winding-number occupancy of the reference mesh on an r^3 grid over [lo, hi]^3 (paper Alg. 1; Alg. 2 / auto for open meshes)";
  s.params.Int("resolution", 128, "grid nodes per axis (paper: 32, 64, 128, 256)", 2, 2048)
      .Choice("method", "fast", {"fast", "exact", "naive", "ray_parity"},
              "fast: exact sign by flood fill (closed) or hierarchy + exact band (open); exact: O(#F) sum per node; naive: eq. 4; ray_parity: Embree parity")
      .Choice("output", "occupancy", {"occupancy", "winding"}, "volume values: 0/1 occupancy or the winding number")
      .Choice("open_mesh", "auto", {"auto", "none", "flip_dup"},
              "auto: threshold + thin shell on sheet faces; none: threshold; flip_dup: the paper's Alg. 2")
      .Choice("orientation", "abs", {"abs", "as_is"}, "abs: |w| > 1/2 (inward meshes work); as_is: w > 1/2")
      .Double("epsilon", 0.01, "Alg. 2 offset (paper 0.01); auto: minimum shell thickness", 0.0, 1e9)
      .Double("beta", 2.0, "hierarchy far-field acceptance ratio (open meshes)", 1.0, 1e9)
      .Double("exact_band", 0.1, "hierarchy: exact sum where ||w| - 1/2| < band", 0.0, 0.5)
      .Double("lo", -1.0, "grid lower bound on every axis (paper: meshes normalised to [-1, 1])")
      .Double("hi", 1.0, "grid upper bound on every axis");
  s.factory = FunctionStage([](Context& ctx, CaseData& d, const ParamMap& p) {
    const Mesh& m = d.RequireReference("voxelize");
    VoxelizeOptions o;
    o.method = p.GetString("method");
    o.output = p.GetString("output");
    o.open_mesh = p.GetString("open_mesh");
    o.orientation = p.GetString("orientation");
    o.epsilon = p.GetDouble("epsilon");
    o.beta = p.GetDouble("beta");
    o.exact_band = p.GetDouble("exact_band");
    const double lo = p.GetDouble("lo"), hi = p.GetDouble("hi");
    const GridInfo g = CubeGrid(static_cast<int>(p.GetInt("resolution")), Vec3::Constant(lo), Vec3::Constant(hi));
    VoxelizeReport rep;
    const auto t0 = std::chrono::steady_clock::now();
    d.volume = Voxelize(m, g, o, &rep);
    d.SetMetric("vox_seconds", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    d.SetMetric("vox_occupied", static_cast<double>(rep.occupied));
    d.SetMetric("vox_exact_evals", static_cast<double>(rep.exact_evaluations));
    d.SetMetric("vox_components", static_cast<double>(rep.components));
    d.SetMetric("vox_sheet_faces", static_cast<double>(rep.sheet_faces));
    if (rep.dropped_faces > 0) ctx.Warn("voxelize: dropped " + std::to_string(rep.dropped_faces) + " degenerate face(s)");
    ctx.Info("voxelize: path " + rep.path + ", " + std::to_string(rep.unbalanced_edges) + " unbalanced edge(s), " +
             std::to_string(rep.occupied) + " occupied node(s)");
  });
  r.Register(std::move(s));
}

void RegisterVolumeMc(Registry& r) {
  StageInfo s;
  s.name = "volume_mc";
  s.role = Role::kOther;
  s.doc = "marching cubes of the voxelizer's volume (inside = value > level), the paper's re-meshing step";
  s.params.Double("level", 0.5, "iso-value (paper: 0.5)");
  s.factory = FunctionStage([](Context&, CaseData& d, const ParamMap& p) {
    if (!d.volume) throw Error("volume_mc needs a volume: put a voxelizer (e.g. voxelize) before it");
    d.output = VolumeToMesh(*d.volume, p.GetDouble("level"));
    if (d.output->NumFaces() == 0) throw Error("volume_mc: the volume has no node above the level (empty output)");
  });
  r.Register(std::move(s));
}

void RegisterLaplacianSmooth(Registry& r) {
  StageInfo s;
  s.name = "laplacian_smooth";
  s.role = Role::kOther;
  s.doc = "trimesh filter_laplacian on the output mesh: equal weights, explicit steps, volume constraint (paper: 10 it., lambda 0.15)";
  s.params.Int("iterations", 10, "smoothing iterations (paper: 10)", 0, 100000)
      .Double("lambda", 0.15, "step size (paper: 0.15)", 0.0, 1.0)
      .Bool("volume_constraint", true, "rescale about the origin to the initial volume after each step (trimesh default)");
  s.factory = FunctionStage([](Context&, CaseData& d, const ParamMap& p) {
    LaplacianSmoothOptions o;
    o.iterations = static_cast<int>(p.GetInt("iterations"));
    o.lambda = p.GetDouble("lambda");
    o.volume_constraint = p.GetBool("volume_constraint");
    d.output = LaplacianSmooth(d.RequireOutput("laplacian_smooth"), o);
  });
  r.Register(std::move(s));
}

void RegisterDophMetrics(Registry& r) {
  StageInfo s;
  s.name = "doph_metrics";
  s.role = Role::kEvaluator;
  s.doc = "the voxelization paper's metrics: Chamfer mean(d1)+mean(d2), squared variant, Hausdorff, over area-uniform samples, mean and std over repeats";
  s.params.Int("samples", 20000, "area-uniform samples per mesh (paper: 20 000)", 1, 100000000)
      .Int("repeats", 3, "independent draws (paper: 3); *_std is their sample std", 1, 1000);
  s.outputs = {"doph_chamfer", "doph_chamfer_std", "doph_chamfer_sq", "doph_chamfer_sq_std", "doph_hausdorff",
               "doph_hausdorff_std"};
  s.factory = FunctionStage([](Context& ctx, CaseData& d, const ParamMap& p) {
    const DophMetrics m = ComputeDophMetrics(d.RequireOutput("doph_metrics"), d.RequireReference("doph_metrics"),
                                             p.GetInt("samples"), static_cast<int>(p.GetInt("repeats")),
                                             ctx.StreamSeed("doph_metrics"));
    d.SetMetric("doph_chamfer", m.chamfer);
    d.SetMetric("doph_chamfer_std", m.chamfer_std);
    d.SetMetric("doph_chamfer_sq", m.chamfer_sq);
    d.SetMetric("doph_chamfer_sq_std", m.chamfer_sq_std);
    d.SetMetric("doph_hausdorff", m.hausdorff);
    d.SetMetric("doph_hausdorff_std", m.hausdorff_std);
  });
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
