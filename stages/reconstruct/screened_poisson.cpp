// screened_poisson: oriented points -> mesh by screened Poisson surface
// reconstruction (Kazhdan & Hoppe 2013; PCL's port), the reconstructor RFTA
// uses. Defaults follow the official RFTA call where PCL has the parameter.
#include "framework/reconstruct/poisson.h"
#include "stages/builtin.h"

namespace arcs {

void RegisterScreenedPoisson(Registry& r) {
  StageInfo s;
  s.name = "screened_poisson";
  s.role = Role::kReconstructor;
  s.doc = "screened Poisson surface reconstruction of the oriented points (PCL's PoissonRecon port; RFTA's sPSR)";
  const PoissonOptions def;
  s.params
      .Int("depth", def.depth,
           "maximum octree depth (2-12); 0 = automatic: finest cell ~ half the point spacing, clamped to [6, 10]",
           0, 12)
      .Int("depth_offset", def.depth_offset,
           "added to the automatic depth (depth 0): -1/-2 = coarser and faster (RFTA's fine-tuning)", -8, 4)
      .Int("min_depth", def.min_depth, "depth up to which the octree is complete (PoissonRecon fullDepth)", 0, 12)
      .Double("point_weight", def.point_weight,
              "screening weight (PCL's scale: 400 here ~ PoissonRecon's 10 in RFTA, measured; 0 = unscreened)", 0.0, 1e6)
      .Double("samples_per_node", def.samples_per_node,
              "minimum points per octree leaf (RFTA: 1.5; 15-20 for noisy points)", 0.5, 100.0)
      .Double("scale", def.scale, "reconstruction cube side / bounding-box extent of the points", 1.01, 16.0)
      .Bool("manifold", def.manifold, "split marching-cubes polygons at their barycentre (manifold output)")
      .Int("threads", def.threads,
           "OpenMP threads inside PCL; only 1 is deterministic (set OMP_WAIT_POLICY=PASSIVE for more)", 1, 256)
      .Int("open_retries", def.open_retries,
           "an open output is solved again with a 4x weaker point weight, up to this many times (0 = never)", 0, 10)
      .Choice("backend", "pcl", {"pcl", "open3d"},
              "pcl: pcl::Poisson (PoissonRecon ~v5 port, FEM degree 2); open3d: Open3D 0.16's PoissonRecon 12 "
              "(FEM degree 1, Neumann, 1.5 samples/node, area-normalised weight fixed at 2; depth, scale, threads only)")
      .Bool("area_normalized", false,
            "point_weight in PoissonRecon's units (the official RFTA: 10), i.e. scaled by the estimated sample "
            "area in the reconstruction cube; false: PCL's own units (divided by the point count)");
  s.outputs = {"poisson_depth", "poisson_point_weight"};
  s.factory = FunctionStage([](Context& ctx, CaseData& d, const ParamMap& p) {
    if (!d.points || !d.points->HasNormals()) {
      throw Error("screened_poisson needs oriented points (points with normals) from an earlier stage");
    }
    PoissonOptions o;
    o.depth = static_cast<int>(p.GetInt("depth"));
    o.min_depth = static_cast<int>(p.GetInt("min_depth"));
    o.depth_offset = static_cast<int>(p.GetInt("depth_offset"));
    o.point_weight = p.GetDouble("point_weight");
    o.samples_per_node = p.GetDouble("samples_per_node");
    o.scale = p.GetDouble("scale");
    o.manifold = p.GetBool("manifold");
    o.threads = static_cast<int>(p.GetInt("threads"));
    o.open_retries = static_cast<int>(p.GetInt("open_retries"));
    o.backend = p.GetString("backend") == "open3d" ? PoissonOptions::Backend::kOpen3d : PoissonOptions::Backend::kPcl;
    o.area_normalized = p.GetBool("area_normalized");
    o.Check();
    // Resolve the automatic depth here so the row records the depth used.
    if (o.depth == 0) o.depth = AutoPoissonDepth(*d.points, o);
    double used = o.point_weight;
    d.output = ReconstructPoisson(*d.points, o, ctx, &used);
    d.SetMetric("poisson_depth", o.depth);
    d.SetMetric("poisson_point_weight", used);
  });
  r.Register(std::move(s));
}

}  // namespace arcs
