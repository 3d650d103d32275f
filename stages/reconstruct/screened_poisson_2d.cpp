// screened_poisson_2d: oriented 2D points -> closed polylines by our 2D
// screened Poisson (the reconstructor of 2D RFTA), and the mapping of the 3D
// `screened_poisson` presets to it on 2D samples.
#include "stages/reconstruct/screened_poisson_2d.h"

#include "framework/reconstruct/poisson2d.h"
#include "registry/bind.h"
#include "stages/builtin.h"
#include "stages/twins_2d.h"

namespace arcs {

StageSpec PlanarReconstructorFor(const StageSpec& spec, const Registry* registry) {
  if (!registry) throw Error("rfta (2D): needs the case's registry to run its reconstructor");
  const std::string twin = TwinIn2D(spec.stage);
  if (twin.empty()) return spec;  // a 2D (or dimension-free) reconstructor: as given
  // The twin of screened_poisson (the only reconstructor with one): a
  // coarser 3D preset (depth_offset < 0, RFTA's tuning reconstructor: -3)
  // becomes one power of two coarser per three octree levels.
  ParamMap given;
  if (spec.params.Has("depth_offset")) {
    const std::int64_t d = spec.params.GetInt("depth_offset");
    const std::int64_t shift = d >= 0 ? 0 : -((-d + 2) / 3);
    if (shift != 0) given.Set("resolution_shift", std::max<std::int64_t>(shift, -4));
  }
  return StageSpec{twin, registry->Resolve(twin, given)};
}

namespace {

Binder<Poisson2DOptions> Poisson2DParams() {
  using O = Poisson2DOptions;
  return Binder<O>()
      .Int("resolution", &O::resolution,
           "grid cells per side; 0 = automatic: 4 sqrt(N) rounded up to a power of two, in [64, 1024]", Closed(0, 4096))
      .Int("resolution_shift", &O::resolution_shift, "added to the automatic power of two (-1 = half as fine)",
           Closed(-4, 4))
      .Double("screening", &O::screening,
              "screening weight alpha per unit curve length in cells (paper: 10; 0 = unscreened)", Closed(0.0, 1e6))
      .Double("scale", &O::scale, "grid side / largest extent of the points", LeftOpen(1.0, 16.0))
      .Double("smoothing", &O::smoothing, "splatting radius of each normal, in multiples of its point spacing",
              Closed(0.0, 16.0))
      .Int("neighbours", &O::neighbours, "k of the k-nearest-neighbour density estimate", Closed(1, 64));
}

void RunScreenedPoisson2D(Context& ctx, CaseData& d, const Poisson2DOptions& o, const ParamMap&) {
  if (!d.points->HasNormals()) throw Error("needs oriented points (points with normals) from an earlier stage");
  Poisson2DInfo info;
  d.output_curve = ReconstructPoisson2D(*d.points, o, ctx, &info);
  d.SetMetric("poisson2d_resolution", info.resolution);
}

}  // namespace

void RegisterScreenedPoisson2D(Registry& r) {
  StageInfo s = DeclareStage(
      "screened_poisson_2d", Role::kReconstructor,
      "2D screened Poisson (our own, on a regular grid): oriented 2D points -> closed polylines (RFTA's 2D sPSR)",
      {Slot::kPoints}, {Slot::kOutput}, k2D);
  BindStage<Poisson2DOptions>(s, Poisson2DParams(), RunScreenedPoisson2D);
  s.outputs = {"poisson2d_resolution"};
  r.Register(std::move(s));
}

}  // namespace arcs
