// sdf_sweep: the pseudo-SDF of a swept volume (paper §5.3, Fig. 25) on the
// paper's grid protocol. The reference becomes the swept solid's surface.
#include "framework/error.h"
#include "framework/geometry/marching_cubes.h"
#include "framework/sdf/pseudo_sdf.h"
#include "registry/bind.h"
#include "stages/builtin.h"

namespace arcs {

namespace {

// The stage's settings: the grid, the sweep (its translation as three
// numbers, defaults from SweepOptions{}), and the finer grid of the reference
// surface (a stage-level setting, not the algorithm's).
struct SdfSweepOptions {
  SdfGridOptions grid;
  double dx = SweepOptions{}.translation.x();
  double dy = SweepOptions{}.translation.y();
  double dz = SweepOptions{}.translation.z();
  SweepOptions sweep;
  int reference_n = 128;  // 0 keeps the unswept mesh
  SweepOptions Sweep() const {
    SweepOptions s = sweep;
    s.translation = Vec3(dx, dy, dz);
    return s;
  }
  void Check() const {
    grid.Check();
    Sweep().Check();
    ARCS_CHECK_OPTION(reference_n >= 0 && reference_n <= 1024, "reference_n", reference_n, "in [0, 1024]");
  }
};

Binder<SdfGridOptions> SweepGridParams() {
  using O = SdfGridOptions;
  return Binder<O>()
      .Int("n", &O::n, "grid cells per axis ((n+1)^3 nodes of linspace(lo,hi,n+1)^3)", Closed(1, SdfGridOptions::kMaxN))
      .Double("lo", &O::lo, "lower grid bound on every axis")
      .Double("hi", &O::hi, "upper grid bound on every axis (greater than lo)");
}

Binder<SweepOptions> SweepParams() {
  using O = SweepOptions;
  return Binder<O>()
      .Double("angle", &O::angle_deg,
              "rotation over the whole sweep, degrees, about z through the bounding-box centre")
      .Int("steps", &O::steps, "poses K of the discretised sweep", Closed(2, 4096));
}

Binder<SdfSweepOptions> SdfSweepParams() {
  using O = SdfSweepOptions;
  return Binder<O>()
      .Group(&O::grid, SweepGridParams())
      .Double("dx", &O::dx, "translation over the whole sweep, x")
      .Double("dy", &O::dy, "translation over the whole sweep, y")
      .Double("dz", &O::dz, "translation over the whole sweep, z")
      .Group(&O::sweep, SweepParams())
      .Int("reference_n", &O::reference_n,
           "the reference surface (for the metrics) is marching cubes of the pseudo-SDF on this finer grid; "
           "0 keeps the unswept mesh",
           Closed(0, 1024));
}

void RunSdfSweep(Context& ctx, CaseData& d, const SdfSweepOptions& opt, const ParamMap&) {
  const SweepOptions sw = opt.Sweep();
  const Mesh& mesh = *d.reference;
  d.samples = SampleSweptSdfGrid(mesh, sw, opt.grid, ctx);
  if (opt.reference_n > 0) {
    SdfGridOptions fine = opt.grid;
    fine.n = opt.reference_n;
    const SdfSamples ref = SampleSweptSdfGrid(mesh, sw, fine, ctx);
    Mesh surface = MarchingCubes(ref.values, *ref.grid, 0.0);
    if (surface.Empty()) throw Error("sdf_sweep: the swept solid's reference surface is empty");
    d.reference = std::move(surface);
  }
}

}  // namespace

void RegisterSdfSweep(Registry& r) {
  StageInfo s = DeclareStage("sdf_sweep", Role::kSdfSampler,
                             "pseudo-SDF of the reference swept along a path: min over poses of its SDF (paper Fig. 25)",
                             {Slot::kReference}, {Slot::kSamples, Slot::kReference}, k3D);
  BindStage<SdfSweepOptions>(s, SdfSweepParams(), RunSdfSweep);
  r.Register(std::move(s));
}

}  // namespace arcs
