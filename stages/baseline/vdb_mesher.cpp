// vdb_mesher: OpenVDB's tools::volumeToMesh on grid SDF samples (optional at
// build: without libopenvdb-dev the stage is listed but throws).
#include "framework/sdfmesh/sdf_input.h"
#include "framework/sdfmesh/vdb_mesher.h"
#include "stages/builtin.h"

namespace arcs {

void RegisterVdbMesher(Registry& r) {
  StageInfo s;
  s.name = "vdb_mesher";
  s.role = Role::kSdfToMesh;
  s.doc = std::string("OpenVDB 10 volumeToMesh on grid SDF samples (dual mesher, vertex = mean of the cell's edge "
                      "crossings; adaptivity merges flat regions)") +
          (VdbMesherAvailable() ? "" : " [this build has no OpenVDB: install libopenvdb-dev]");
  s.params.Double("level", 0.0, "iso-value extracted (OpenVDB's isovalue, default 0)")
      .Double("adaptivity", 0.0, "0 = uniform mesh ... 1 = merge flat regions as much as possible (OpenVDB's default 0)",
              0.0, 1.0)
      .Bool("relax_disoriented_triangles", true, "OpenVDB's relaxDisorientedTriangles (its default true)");
  s.factory = FunctionStage([](Context&, CaseData& d, const ParamMap& p) {
    const SdfSamples& sm = d.RequireSamples("vdb_mesher");
    VdbMesherOptions o;
    o.isovalue = p.GetDouble("level");
    o.adaptivity = p.GetDouble("adaptivity");
    o.relax_disoriented_triangles = p.GetBool("relax_disoriented_triangles");
    o.Check();
    CheckSdfToMeshInput(sm, "vdb_mesher", /*need_grid=*/true, o.isovalue);
    d.output = VdbVolumeToMesh(sm.values, *sm.grid, o);
  });
  r.Register(std::move(s));
}

}  // namespace arcs
