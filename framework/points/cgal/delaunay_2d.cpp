// The only translation unit that sees CGAL's Delaunay_triangulation_2.
#include "framework/points/delaunay_2d.h"

#include "framework/error.h"

#ifdef ARCS_WITH_CGAL
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <utility>
#endif

namespace arcs::points_detail {

#ifdef ARCS_WITH_CGAL

namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Triangulation_vertex_base_with_info_2<int, K>;
using Tds = CGAL::Triangulation_data_structure_2<Vb>;
using Dt = CGAL::Delaunay_triangulation_2<K, Tds>;
}  // namespace

std::vector<std::array<int, 3>> Delaunay2D(const std::vector<double>& x, const std::vector<double>& y,
                                           int* merged) {
  if (x.size() != y.size()) throw Error("Delaunay2D: x and y differ in length");
  Dt dt;
  Dt::Face_handle hint;
  int dup = 0;
  // Insertion in input order (callers put the corners first): a point at the
  // position of an existing vertex returns that vertex, whose info is kept.
  for (size_t i = 0; i < x.size(); ++i) {
    const std::size_t before = dt.number_of_vertices();
    Dt::Vertex_handle v = dt.insert(K::Point_2(x[i], y[i]), hint);
    if (dt.number_of_vertices() == before) {
      ++dup;
    } else {
      v->info() = static_cast<int>(i);
    }
    hint = v->face();
  }
  if (merged) *merged = dup;
  std::vector<std::array<int, 3>> tris;
  if (dt.dimension() < 2) return tris;
  tris.reserve(dt.number_of_faces());
  for (auto f = dt.finite_faces_begin(); f != dt.finite_faces_end(); ++f)
    tris.push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});  // CCW in CGAL
  return tris;
}

#else

std::vector<std::array<int, 3>> Delaunay2D(const std::vector<double>&, const std::vector<double>&, int*) {
  throw Error("graph_voronoi full_resolution: arcs was built without CGAL (install libcgal-dev and rebuild)");
}

#endif

}  // namespace arcs::points_detail
