// vdb_mesher: OpenVDB's tools::volumeToMesh on grid SDF samples (optional at
// build: without libopenvdb-dev the stage is listed but throws).
#include "framework/sdfmesh/sdf_input.h"
#include "framework/sdfmesh/vdb_mesher.h"
#include "registry/bind.h"
#include "stages/builtin.h"

namespace arcs {

namespace {

Binder<VdbMesherOptions> VdbMesherParams() {
  using O = VdbMesherOptions;
  return Binder<O>()
      .Double("level", &O::isovalue, "iso-value extracted (OpenVDB's isovalue, default 0)")
      .Double("adaptivity", &O::adaptivity,
              "0 = uniform mesh ... 1 = merge flat regions as much as possible (OpenVDB's default 0)", Closed(0.0, 1.0))
      .Bool("relax_disoriented_triangles", &O::relax_disoriented_triangles,
            "OpenVDB's relaxDisorientedTriangles (its default true)");
}

void RunVdbMesher(Context&, CaseData& d, const VdbMesherOptions& o, const ParamMap&) {
  const SdfSamples& sm = *d.samples;
  CheckSdfToMeshInput(sm, "vdb_mesher", /*need_grid=*/true, o.isovalue);
  d.output = VdbVolumeToMesh(sm.values, *sm.grid, o);
}

}  // namespace

void RegisterVdbMesher(Registry& r) {
  StageInfo s = DeclareStage(
      "vdb_mesher", Role::kSdfToMesh,
      std::string("OpenVDB 10 volumeToMesh on grid SDF samples (dual mesher, vertex = mean of the cell's edge "
                  "crossings; adaptivity merges flat regions)") +
          (VdbMesherAvailable() ? "" : " [this build has no OpenVDB: install libopenvdb-dev]"),
      {Slot::kSamples}, {Slot::kOutput}, k3D);
  BindStage<VdbMesherOptions>(s, VdbMesherParams(), RunVdbMesher);
  r.Register(std::move(s));
}

}  // namespace arcs
