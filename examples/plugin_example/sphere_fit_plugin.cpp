// An example arcs plugin: one stage, `example_sphere_fit`, an (intentionally
// simple) SDF -> mesh method: the sphere centred at the deepest inside sample
// with radius |s| there. It shows the whole plugin contract
// (docs/adding_a_stage.md walks through it):
//   * an Options struct with commented defaults and Check(), the algorithm's
//     own validity test;
//   * one declaration per parameter (Binder, registry/bind.h): name, field,
//     doc and bounds, from which come the schema, `arcs describe`, `--set`,
//     the Python keywords and the load-time check;
//   * the stage's contract (DeclareStage): it reads the SDF samples, writes
//     the output mesh, works in 3D; the loader refuses a pipeline that cannot
//     feed it, and Stage::Run checks it again and prefixes errors;
//   * the ARCS_PLUGIN macro that exports the versioned C entry point;
//   * framework functions (MakeIcosphere) resolved from the host.
#include "framework/geometry/builtin_shapes.h"
#include "registry/bind.h"
#include "registry/plugin_api.h"
#include "registry/registry.h"

namespace {

struct SphereFitOptions {
  int subdivisions = 3;  // icosphere subdivisions of the output (3: 642 vertices)
  void Check() const {
    ARCS_CHECK_OPTION(subdivisions >= 0 && subdivisions <= 7, "subdivisions", subdivisions, "in [0, 7]");
  }
};

arcs::Mesh SphereFit(const arcs::SdfSamples& sm, const SphereFitOptions& o) {
  o.Check();
  Eigen::Index best;
  const double s = sm.values.minCoeff(&best);
  if (!(s < 0)) throw arcs::Error("no sample is inside (all SDF values >= 0)");
  arcs::Vec3 c = arcs::Vec3::Zero();
  for (int a = 0; a < sm.dim; ++a) c[a] = sm.points(best, a);
  return arcs::MakeIcosphere(-s, o.subdivisions, c);
}

arcs::Binder<SphereFitOptions> SphereFitParams() {
  return arcs::Binder<SphereFitOptions>().Int("subdivisions", &SphereFitOptions::subdivisions,
                                              "icosphere subdivisions of the output", arcs::Closed(0, 7));
}

// The stage body: the contract guarantees d.samples is there.
void RunSphereFit(arcs::Context&, arcs::CaseData& d, const SphereFitOptions& o, const arcs::ParamMap&) {
  d.output = SphereFit(*d.samples, o);
}

void RegisterStages(arcs::Registry& registry) {
  arcs::StageInfo s = arcs::DeclareStage("example_sphere_fit", arcs::Role::kSdfToMesh,
                                         "example plugin: sphere at the deepest inside sample, radius |s| there",
                                         {arcs::Slot::kSamples}, {arcs::Slot::kOutput}, arcs::k3D);
  arcs::BindStage<SphereFitOptions>(s, SphereFitParams(), RunSphereFit);
  registry.Register(std::move(s));
}

}  // namespace

ARCS_PLUGIN("example_sphere_fit", "1.0", RegisterStages)
