// An example arcs plugin: one stage, `example_sphere_fit`, an (intentionally
// simple) SDF -> mesh method: the sphere centred at the deepest inside sample
// with radius |s| there. It shows the whole plugin contract:
//   * a registration function that fills StageInfo (name, role, doc, schema),
//   * the ARCS_PLUGIN macro that exports the versioned C entry point,
//   * use of framework functions (MakeIcosphere) resolved from the host.
#include "framework/geometry/builtin_shapes.h"
#include "registry/plugin_api.h"
#include "registry/registry.h"

namespace {

void RegisterStages(arcs::Registry& registry) {
  arcs::StageInfo s;
  s.name = "example_sphere_fit";
  s.role = arcs::Role::kSdfToMesh;
  s.doc = "example plugin: sphere at the deepest inside sample, radius |s| there";
  s.params.Int("subdivisions", 3, "icosphere subdivisions of the output", 0, 7);
  s.factory = arcs::FunctionStage([](arcs::Context&, arcs::CaseData& d, const arcs::ParamMap& p) {
    const arcs::SdfSamples& sm = d.RequireSamples("example_sphere_fit");
    Eigen::Index best;
    const double s = sm.values.minCoeff(&best);
    if (!(s < 0)) throw arcs::Error("example_sphere_fit: no sample is inside (all SDF values >= 0)");
    arcs::Vec3 c = arcs::Vec3::Zero();
    for (int a = 0; a < sm.dim; ++a) c[a] = sm.points(best, a);
    d.output = arcs::MakeIcosphere(-s, static_cast<int>(p.GetInt("subdivisions")), c);
  });
  registry.Register(std::move(s));
}

}  // namespace

ARCS_PLUGIN("example_sphere_fit", "1.0", RegisterStages)
