// The only translation unit that sees CGAL's Alpha_shape_3.
#include "framework/points/backends.h"

#include "framework/error.h"

#include <Eigen/Geometry>

#ifdef ARCS_WITH_CGAL
#include <CGAL/Alpha_shape_3.h>
#include <CGAL/Alpha_shape_cell_base_3.h>
#include <CGAL/Alpha_shape_vertex_base_3.h>
#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <utility>
#endif

namespace arcs::points_detail {

#ifdef ARCS_WITH_CGAL

bool CgalAvailable() { return true; }

namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vbi = CGAL::Triangulation_vertex_base_with_info_3<int, K>;
using Vb = CGAL::Alpha_shape_vertex_base_3<K, Vbi>;
using Cb = CGAL::Alpha_shape_cell_base_3<K>;
using Tds = CGAL::Triangulation_data_structure_3<Vb, Cb>;
using Delaunay = CGAL::Delaunay_triangulation_3<K, Tds, CGAL::Fast_location>;
using AlphaShape = CGAL::Alpha_shape_3<Delaunay>;
}  // namespace

Mesh CgalAlphaShape(const MatrixX3d& P, double alpha_sq, double* used_alpha_sq, double optimal_scale) {
  std::vector<std::pair<K::Point_3, int>> pts;
  pts.reserve(P.rows());
  for (int i = 0; i < P.rows(); ++i) pts.emplace_back(K::Point_3(P(i, 0), P(i, 1), P(i, 2)), i);
  Delaunay dt(pts.begin(), pts.end());
  if (dt.dimension() < 3) throw Error("alpha_shape: the points are coplanar or collinear (no volume to bound)");
  AlphaShape as(dt, alpha_sq, AlphaShape::REGULARIZED);  // takes dt's triangulation
  if (alpha_sq <= 0) {
    const auto opt = as.find_optimal_alpha(1);
    if (opt == as.alpha_end()) throw Error("alpha_shape: CGAL found no optimal alpha");
    as.set_alpha(*opt * optimal_scale * optimal_scale);
  }
  if (used_alpha_sq) *used_alpha_sq = CGAL::to_double(as.get_alpha());
  std::vector<std::array<int, 3>> faces;
  for (auto fit = as.finite_facets_begin(); fit != as.finite_facets_end(); ++fit) {
    if (as.classify(*fit) != AlphaShape::REGULAR) continue;
    auto c = fit->first;
    int i = fit->second;
    // Make c the interior cell (infinite cells are exterior).
    if (as.is_infinite(c) || as.classify(c) != AlphaShape::INTERIOR) {
      const auto n = c->neighbor(i);
      i = n->index(c);
      c = n;
    }
    std::array<int, 3> f;
    int m = 0;
    for (int j = 0; j < 4; ++j)
      if (j != i) f[m++] = c->vertex(j)->info();
    // Wind outward: the face normal points away from the cell's fourth vertex.
    const Vec3 a = P.row(f[0]), b = P.row(f[1]), cc = P.row(f[2]);
    const Vec3 opp = P.row(c->vertex(i)->info());
    if ((b - a).cross(cc - a).dot(opp - a) > 0) std::swap(f[1], f[2]);
    faces.push_back(f);
  }
  Mesh m;
  m.V = P;
  m.F.resize(static_cast<int>(faces.size()), 3);
  for (int f = 0; f < static_cast<int>(faces.size()); ++f)
    for (int k = 0; k < 3; ++k) m.F(f, k) = faces[f][k];
  return m;
}

#else

bool CgalAvailable() { return false; }

Mesh CgalAlphaShape(const MatrixX3d&, double, double*, double) {
  throw Error("alpha_shape: arcs was built without CGAL: install libcgal-dev and reconfigure (ARCS_WITH_CGAL)");
}

#endif

}  // namespace arcs::points_detail
