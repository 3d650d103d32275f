// The only translation unit that sees CGAL's Regular_triangulation_3.
#include "framework/error.h"
#include "framework/sdfmesh/backends.h"

#ifdef ARCS_WITH_CGAL
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Regular_triangulation_3.h>
#include <CGAL/Regular_triangulation_cell_base_3.h>
#include <CGAL/Regular_triangulation_vertex_base_3.h>
#include <CGAL/Triangulation_data_structure_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <utility>
#endif

namespace arcs::sdfmesh_detail {

#ifdef ARCS_WITH_CGAL

bool CgalAvailable() { return true; }

namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb0 = CGAL::Regular_triangulation_vertex_base_3<K>;
using Vb = CGAL::Triangulation_vertex_base_with_info_3<int, K, Vb0>;
using Cb = CGAL::Regular_triangulation_cell_base_3<K>;
using Tds = CGAL::Triangulation_data_structure_3<Vb, Cb>;
using Rt = CGAL::Regular_triangulation_3<K, Tds>;
using Wp = K::Weighted_point_3;
}  // namespace

std::vector<std::array<int, 4>> RegularTetrahedraCrossing(const MatrixXd& P, const VectorXd& weights,
                                                          const std::vector<std::uint8_t>& inside,
                                                          std::int64_t* num_vertices, std::int64_t* num_tetrahedra,
                                                          int* dimension) {
  std::vector<std::pair<Wp, int>> pts;
  pts.reserve(P.rows());
  for (Eigen::Index i = 0; i < P.rows(); ++i)
    pts.emplace_back(Wp(K::Point_3(P(i, 0), P(i, 1), P(i, 2)), weights[i]), static_cast<int>(i));
  Rt rt(pts.begin(), pts.end());  // spatially sorted insertion
  *num_vertices = static_cast<std::int64_t>(rt.number_of_vertices());
  *dimension = rt.dimension();
  *num_tetrahedra = 0;
  std::vector<std::array<int, 4>> out;
  if (rt.dimension() < 3) return out;
  for (auto c = rt.finite_cells_begin(); c != rt.finite_cells_end(); ++c) {
    ++*num_tetrahedra;
    std::array<int, 4> t;
    int in = 0;
    for (int k = 0; k < 4; ++k) {
      t[k] = c->vertex(k)->info();
      in += inside[t[k]];
    }
    if (in > 0 && in < 4) out.push_back(t);
  }
  return out;
}

#else

bool CgalAvailable() { return false; }

std::vector<std::array<int, 4>> RegularTetrahedraCrossing(const MatrixXd&, const VectorXd&, const std::vector<std::uint8_t>&,
                                                          std::int64_t*, std::int64_t*, int*) {
  throw Error("power_diagram: arcs was built without CGAL: install libcgal-dev and rebuild (ARCS_WITH_CGAL)");
}

#endif

}  // namespace arcs::sdfmesh_detail
