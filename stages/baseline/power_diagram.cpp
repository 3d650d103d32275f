// power_diagram: marching tetrahedra on the regular triangulation of the SDF
// samples weighted by s^2 (Kohlbrenner & Alexa 2025), CGAL behind
// framework/sdfmesh/backends.h. Grid or scattered samples.
#include "framework/sdfmesh/power_diagram.h"
#include "stages/builtin.h"

namespace arcs {

void RegisterPowerDiagram(Registry& r) {
  StageInfo s;
  s.name = "power_diagram";
  s.role = Role::kSdfToMesh;
  s.doc = std::string("isosurface on the power diagram of the SDF spheres (Kohlbrenner & Alexa 2025): CGAL regular "
                      "triangulation weighted by s^2, marching tetrahedra; grid or scattered samples") +
          (PowerDiagramAvailable() ? "" : " [this build has no CGAL: install libcgal-dev]");
  s.params.Double("level", 0.0, "iso-value extracted (inside iff s < level; the weights stay s^2)")
      .Bool("weighted", true, "weights s^2 (the paper); false: plain Delaunay tetrahedralisation of the samples")
      .Choice("vertex", "linear", {"linear", "sphere_gap"},
              "point on a crossed edge: zero of the linear interpolation, or the middle of the gap between the two "
              "spheres along the edge");
  s.outputs = {"power_hidden", "power_tetrahedra"};
  s.factory = FunctionStage([](Context&, CaseData& d, const ParamMap& p) {
    const SdfSamples& sm = d.RequireSamples("power_diagram");
    PowerDiagramOptions o;
    o.isovalue = p.GetDouble("level");
    o.weighted = p.GetBool("weighted");
    o.vertex = p.GetString("vertex") == "sphere_gap" ? PowerDiagramOptions::Vertex::kSphereGap
                                                     : PowerDiagramOptions::Vertex::kLinear;
    PowerDiagramStats st;
    d.output = PowerDiagramContour(sm, o, &st);
    d.SetMetric("power_hidden", static_cast<double>(st.hidden));
    d.SetMetric("power_tetrahedra", static_cast<double>(st.tetrahedra));
  });
  r.Register(std::move(s));
}

}  // namespace arcs
