// The only translation unit that sees CGAL's advancing front surface
// reconstruction.
#include "framework/points/backends.h"

#include "framework/error.h"

#ifdef ARCS_WITH_CGAL
#include <CGAL/Advancing_front_surface_reconstruction.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <array>
#include <iterator>
#endif

namespace arcs::points_detail {

#ifdef ARCS_WITH_CGAL

Mesh CgalAdvancingFront(const MatrixX3d& P, double radius_ratio_bound, double beta) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  std::vector<K::Point_3> pts;
  pts.reserve(P.rows());
  for (int i = 0; i < P.rows(); ++i) pts.emplace_back(P(i, 0), P(i, 1), P(i, 2));
  std::vector<std::array<std::size_t, 3>> faces;
  CGAL::advancing_front_surface_reconstruction(pts.begin(), pts.end(), std::back_inserter(faces),
                                               radius_ratio_bound, beta);
  Mesh m;
  m.V = P;
  m.F.resize(static_cast<int>(faces.size()), 3);
  for (int f = 0; f < static_cast<int>(faces.size()); ++f)
    for (int k = 0; k < 3; ++k) m.F(f, k) = static_cast<int>(faces[f][k]);
  return m;
}

#else

Mesh CgalAdvancingFront(const MatrixX3d&, double, double) {
  throw Error("advancing_front: arcs was built without CGAL: install libcgal-dev and reconfigure (ARCS_WITH_CGAL)");
}

#endif

}  // namespace arcs::points_detail
