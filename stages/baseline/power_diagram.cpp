// power_diagram: marching tetrahedra on the regular triangulation of the SDF
// samples weighted by s^2 (Kohlbrenner & Alexa 2025), CGAL behind
// framework/sdfmesh/backends.h. Grid or scattered samples.
#include "framework/sdfmesh/power_diagram.h"
#include "registry/bind.h"
#include "stages/builtin.h"

namespace arcs {

namespace {

Binder<PowerDiagramOptions> PowerDiagramParams() {
  using O = PowerDiagramOptions;
  return Binder<O>()
      .Double("level", &O::isovalue, "iso-value extracted (inside iff s < level; the weights stay s^2)")
      .Bool("weighted", &O::weighted, "weights s^2 (the paper); false: plain Delaunay tetrahedralisation of the samples")
      .Enum("vertex", &O::vertex, kPowerVertexNames,
            "point on a crossed edge: zero of the linear interpolation, or the middle of the gap between the two "
            "spheres along the edge");
}

void RunPowerDiagram(Context&, CaseData& d, const PowerDiagramOptions& o, const ParamMap&) {
  PowerDiagramStats st;
  d.output = PowerDiagramContour(*d.samples, o, &st);
  d.SetMetric("power_hidden", static_cast<double>(st.hidden));
  d.SetMetric("power_tetrahedra", static_cast<double>(st.tetrahedra));
}

}  // namespace

void RegisterPowerDiagram(Registry& r) {
  StageInfo s = DeclareStage(
      "power_diagram", Role::kSdfToMesh,
      std::string("isosurface on the power diagram of the SDF spheres (Kohlbrenner & Alexa 2025): CGAL regular "
                  "triangulation weighted by s^2, marching tetrahedra; grid or scattered samples") +
          (PowerDiagramAvailable() ? "" : " [this build has no CGAL: install libcgal-dev]"),
      {Slot::kSamples}, {Slot::kOutput}, k3D);
  BindStage<PowerDiagramOptions>(s, PowerDiagramParams(), RunPowerDiagram);
  s.outputs = {"power_hidden", "power_tetrahedra"};
  r.Register(std::move(s));
}

}  // namespace arcs
