// sdf_sweep: the pseudo-SDF of a swept volume (paper §5.3, Fig. 25) on the
// paper's grid protocol. The reference becomes the swept solid's surface.
#include "framework/geometry/marching_cubes.h"
#include "framework/sdf/pseudo_sdf.h"
#include "stages/builtin.h"

namespace arcs {

void RegisterSdfSweep(Registry& r) {
  StageInfo s;
  s.name = "sdf_sweep";
  s.role = Role::kSdfSampler;
  s.doc = "pseudo-SDF of the reference swept along a path: min over poses of its SDF (paper Fig. 25)";
  s.params.Int("n", 20, "grid cells per axis ((n+1)^3 nodes of linspace(lo,hi,n+1)^3)", 1, 2048)
      .Double("lo", -1.0, "lower grid bound on every axis")
      .Double("hi", 1.0, "upper grid bound on every axis")
      .Double("dx", 0.3, "translation over the whole sweep, x")
      .Double("dy", 0.0, "translation over the whole sweep, y")
      .Double("dz", 0.0, "translation over the whole sweep, z")
      .Double("angle", 0.0, "rotation over the whole sweep, degrees, about z through the bounding-box centre")
      .Int("steps", 16, "poses K of the discretised sweep", 2, 4096)
      .Int("reference_n", 128,
           "the reference surface (for the metrics) is marching cubes of the pseudo-SDF on this finer grid; "
           "0 keeps the unswept mesh",
           0, 1024);
  s.factory = FunctionStage([](Context& ctx, CaseData& d, const ParamMap& p) {
    SweepOptions sw;
    sw.translation = Vec3(p.GetDouble("dx"), p.GetDouble("dy"), p.GetDouble("dz"));
    sw.angle_deg = p.GetDouble("angle");
    sw.steps = static_cast<int>(p.GetInt("steps"));
    SdfGridOptions g;
    g.n = static_cast<int>(p.GetInt("n"));
    g.lo = p.GetDouble("lo");
    g.hi = p.GetDouble("hi");
    if (!(g.hi > g.lo)) throw OptionError("sdf_sweep: hi must be greater than lo");
    const Mesh& mesh = d.RequireReference("sdf_sweep");
    d.samples = SampleSweptSdfGrid(mesh, sw, g, ctx);
    if (const int rn = static_cast<int>(p.GetInt("reference_n")); rn > 0) {
      SdfGridOptions fine = g;
      fine.n = rn;
      const SdfSamples ref = SampleSweptSdfGrid(mesh, sw, fine, ctx);
      Mesh surface = MarchingCubes(ref.values, *ref.grid, 0.0);
      if (surface.Empty()) throw Error("sdf_sweep: the swept solid's reference surface is empty");
      d.reference = std::move(surface);
    }
  });
  r.Register(std::move(s));
}

}  // namespace arcs
