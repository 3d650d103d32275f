// rasterize: the RFTA paper's empty-space sampler (§4.1, footnote 1, Fig. 10):
// the narrow band of free raster cells around each sign's union of spheres.
#include "framework/rfta/free_space.h"
#include "registry/bind.h"
#include "stages/builtin.h"

namespace arcs {

namespace {

Binder<RasterizeOptions> RasterizeParams() {
  using O = RasterizeOptions;
  return Binder<O>()
      .Int("resolution", &O::resolution,
           "raster cells per axis on the samples' unit box; 0 = official heuristic 64*ceil(N^(1/d)/16)",
           Closed(0, 2048))
      .Int("max_resolution", &O::max_resolution, "cap of the heuristic resolution (official: 1024)", Closed(2, 2048))
      .Double("shrink", &O::shrink, "a cell is occupied if |x-c|^2 <= shrink*r^2 (official CPU: 0.95)",
              LeftOpen(0.0, 1.0))
      .Bool("jitter", &O::jitter, "one uniformly jittered point per cell (official); false = cell centres");
}

void RunRasterize(Context& ctx, CaseData& d, const RasterizeOptions& o, const ParamMap&) {
  RasterizeStats st[2];
  FreeSpaceSamples f = RasterizeFreeSpace(*d.samples, o, ctx, st);
  ctx.Info("rasterize: resolution " + std::to_string(st[0].resolution) + ", " + std::to_string(st[0].band_points) +
           " positive + " + std::to_string(st[1].band_points) + " negative free points");
  d.free_points = PointCloud{std::move(f.points), MatrixX3d()};
  d.free_point_sign = std::move(f.sign);
  d.SetMetric("raster_resolution", st[0].resolution);
  d.SetMetric("free_points", static_cast<double>(d.free_points->Size()));
}

}  // namespace

void RegisterRasterize(Registry& r) {
  StageInfo s = DeclareStage("rasterize", Role::kEmptySpaceSampler,
                             "RFTA free-space samples: free raster cells next to occupied ones, per sign (paper §4.1)",
                             {Slot::kSamples}, {Slot::kFreePoints});
  BindStage<RasterizeOptions>(s, RasterizeParams(), RunRasterize);
  r.Register(std::move(s));
}

}  // namespace arcs
