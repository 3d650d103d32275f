// CGAL's isotropic remeshing behind a plain interface (bench/cgal_remesh.cpp),
// the comparison of rfts_remesh_bench.
#pragma once

#include <vector>

namespace arcs::bench {

// One call of CGAL::Polygon_mesh_processing::isotropic_remeshing on the faces
// flagged in `active` (all when empty), `iterations` rounds, target edge
// length h, including the conversion to and from CGAL's Surface_mesh (what
// the flow would pay per step). Replaces V / F; returns seconds.
double CgalIsotropicRemesh(std::vector<double>* V, std::vector<int>* F, const std::vector<char>& active, double h,
                           int iterations);

}  // namespace arcs::bench
