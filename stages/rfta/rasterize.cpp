// rasterize: the RFTA paper's empty-space sampler (§4.1, footnote 1, Fig. 10):
// the narrow band of free raster cells around each sign's union of spheres.
#include "framework/rfta/free_space.h"
#include "stages/builtin.h"

namespace arcs {

void RegisterRasterize(Registry& r) {
  StageInfo s;
  s.name = "rasterize";
  s.role = Role::kEmptySpaceSampler;
  s.doc = "RFTA free-space samples: free raster cells next to occupied ones, per sign (paper §4.1)";
  s.params
      .Int("resolution", 0,
           "raster cells per axis on the samples' unit box; 0 = official heuristic 64*ceil(N^(1/d)/16)", 0, 2048)
      .Int("max_resolution", 1024, "cap of the heuristic resolution (official: 1024)", 2, 2048)
      .Double("shrink", 0.95, "a cell is occupied if |x-c|^2 <= shrink*r^2 (official CPU: 0.95)", 1e-6, 1.0)
      .Bool("jitter", true, "one uniformly jittered point per cell (official); false = cell centres");
  s.factory = FunctionStage([](Context& ctx, CaseData& d, const ParamMap& p) {
    RasterizeOptions o;
    o.resolution = static_cast<int>(p.GetInt("resolution"));
    o.max_resolution = static_cast<int>(p.GetInt("max_resolution"));
    o.shrink = p.GetDouble("shrink");
    o.jitter = p.GetBool("jitter");
    RasterizeStats st[2];
    FreeSpaceSamples f = RasterizeFreeSpace(d.RequireSamples("rasterize"), o, ctx, st);
    ctx.Info("rasterize: resolution " + std::to_string(st[0].resolution) + ", " +
             std::to_string(st[0].band_points) + " positive + " + std::to_string(st[1].band_points) +
             " negative free points");
    d.free_points = PointCloud{std::move(f.points), MatrixX3d()};
    d.free_point_sign = std::move(f.sign);
    d.SetMetric("raster_resolution", st[0].resolution);
    d.SetMetric("free_points", static_cast<double>(d.free_points->Size()));
  });
  r.Register(std::move(s));
}

}  // namespace arcs
