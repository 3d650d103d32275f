// Isosurface extraction on the power diagram of the SDF samples (Kohlbrenner
// & Alexa, "Isosurface Extraction for Signed Distance Functions using Power
// Diagrams", CGF 2025), for fixed samples (no refinement by new queries).
//
// Every sample (p_i, s_i) is a weighted point with weight s_i^2: the sphere
// of radius |s_i| about p_i. Its regular (weighted Delaunay) triangulation is
// the dual of the power diagram of those spheres; samples whose power cell is
// empty are hidden and take no part. Marching tetrahedra on its finite
// tetrahedra gives the surface: on every edge between a negative
// (s < isovalue: inside) and a non-negative vertex, one point (linear
// interpolation of s, or the middle of the gap between the two spheres along
// the edge), one triangle per tetrahedron with one or three inside vertices,
// two (split along the shorter diagonal) with two, wound outward. Works on
// grid and scattered samples alike. The triangulation is CGAL's
// Regular_triangulation_3 (exact predicates), built sequentially; vertices
// and faces are put in a canonical order (by the sample pairs of their
// edges), so the mesh does not depend on CGAL's cell order or the thread
// count.
#pragma once

#include "framework/types.h"
#include "framework/util/enum_names.h"

#include <cstdint>

namespace arcs {

struct PowerDiagramOptions {
  enum class Vertex { kLinear, kSphereGap };
  double isovalue = 0.0;           // level extracted (inside iff s < isovalue; the weights stay s^2)
  bool weighted = true;            // weights s^2 (the paper); false: plain Delaunay (marching tetrahedra baseline)
  Vertex vertex = Vertex::kLinear; // linear: the zero of the linear interpolation; sphere_gap: the middle of the
                                   // segment between the two spheres along the edge (linear when they overlap)
  void Check() const;
};
// The stage's `vertex` names, in its choice order.
inline constexpr EnumName<PowerDiagramOptions::Vertex> kPowerVertexNames[] = {
    {PowerDiagramOptions::Vertex::kLinear, "linear"}, {PowerDiagramOptions::Vertex::kSphereGap, "sphere_gap"}};

struct PowerDiagramStats {
  std::int64_t hidden = 0;       // samples hidden by the weights (not vertices of the triangulation)
  std::int64_t tetrahedra = 0;   // finite tetrahedra
  std::int64_t crossed = 0;      // tetrahedra the surface crosses
};

// Whether arcs was built with CGAL (ARCS_WITH_CGAL); without it
// PowerDiagramContour throws.
bool PowerDiagramAvailable();

// `samples`: 3D, as CheckSdfToMeshInput(samples, "power_diagram", false).
Mesh PowerDiagramContour(const SdfSamples& samples, const PowerDiagramOptions& options = {},
                         PowerDiagramStats* stats = nullptr);

}  // namespace arcs
