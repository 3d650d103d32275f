// The only translation unit that sees CGAL's normal estimation and
// orientation (Point_set_processing_3).
#include "framework/points/backends.h"

#include "framework/error.h"

#ifdef ARCS_WITH_CGAL
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/jet_estimate_normals.h>
#include <CGAL/mst_orient_normals.h>
#include <CGAL/pca_estimate_normals.h>
#include <CGAL/property_map.h>

#include <tuple>
#endif

namespace arcs::points_detail {

#ifdef ARCS_WITH_CGAL

namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
// Point, normal, input row.
using Row = std::tuple<K::Point_3, K::Vector_3, int>;
using PointMap = CGAL::Nth_of_tuple_property_map<0, Row>;
using NormalMap = CGAL::Nth_of_tuple_property_map<1, Row>;

std::vector<Row> ToRows(const MatrixX3d& P, const MatrixX3d* N) {
  std::vector<Row> rows;
  rows.reserve(P.rows());
  for (int i = 0; i < P.rows(); ++i) {
    K::Vector_3 n(0, 0, 0);
    if (N) n = K::Vector_3((*N)(i, 0), (*N)(i, 1), (*N)(i, 2));
    rows.emplace_back(K::Point_3(P(i, 0), P(i, 1), P(i, 2)), n, i);
  }
  return rows;
}
}  // namespace

MatrixX3d CgalEstimateNormals(const MatrixX3d& P, int k, bool jet) {
  std::vector<Row> rows = ToRows(P, nullptr);
  const auto np = CGAL::parameters::point_map(PointMap()).normal_map(NormalMap());
  // Sequential: deterministic, and CGAL's parallel path needs CGAL built with TBB.
  if (jet) {
    CGAL::jet_estimate_normals<CGAL::Sequential_tag>(rows, k, np);
  } else {
    CGAL::pca_estimate_normals<CGAL::Sequential_tag>(rows, k, np);
  }
  MatrixX3d N(P.rows(), 3);
  for (const auto& r : rows) {
    const auto& n = std::get<1>(r);
    N.row(std::get<2>(r)) << n.x(), n.y(), n.z();
  }
  return N;
}

std::vector<char> CgalMstOrientNormals(const MatrixX3d& P, MatrixX3d* N, int k) {
  std::vector<Row> rows = ToRows(P, N);
  // mst_orient_normals reorders the range: oriented points first.
  const auto first_unoriented =
      CGAL::mst_orient_normals(rows, k, CGAL::parameters::point_map(PointMap()).normal_map(NormalMap()));
  std::vector<char> oriented(P.rows(), 0);
  for (auto it = rows.begin(); it != rows.end(); ++it) {
    const int i = std::get<2>(*it);
    const auto& n = std::get<1>(*it);
    N->row(i) << n.x(), n.y(), n.z();
    oriented[i] = it < first_unoriented ? 1 : 0;
  }
  return oriented;
}

#else

MatrixX3d CgalEstimateNormals(const MatrixX3d&, int, bool) {
  throw Error("estimate_normals: arcs was built without CGAL: install libcgal-dev and reconfigure (ARCS_WITH_CGAL)");
}
std::vector<char> CgalMstOrientNormals(const MatrixX3d&, MatrixX3d*, int) {
  throw Error("estimate_normals: arcs was built without CGAL: install libcgal-dev and reconfigure (ARCS_WITH_CGAL)");
}

#endif

}  // namespace arcs::points_detail
