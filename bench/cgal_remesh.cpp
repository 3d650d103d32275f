// CGAL isotropic remeshing back-end of rfts_remesh_bench (GPL code: benchmark only).
#include "rfts_remesh_backend.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>
#include <CGAL/Surface_mesh.h>

#include <chrono>

namespace arcs::bench {

double CgalIsotropicRemesh(std::vector<double>* V, std::vector<int>* F, const std::vector<char>& active, double h,
                           int iterations) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  using SM = CGAL::Surface_mesh<K::Point_3>;
  namespace PMP = CGAL::Polygon_mesh_processing;
  const auto t0 = std::chrono::steady_clock::now();
  SM m;
  const int nv = static_cast<int>(V->size() / 3), nf = static_cast<int>(F->size() / 3);
  std::vector<SM::Vertex_index> vi(nv);
  for (int v = 0; v < nv; ++v) vi[v] = m.add_vertex(K::Point_3((*V)[3 * v], (*V)[3 * v + 1], (*V)[3 * v + 2]));
  std::vector<SM::Face_index> faces;
  for (int f = 0; f < nf; ++f) {
    const SM::Face_index fi = m.add_face(vi[(*F)[3 * f]], vi[(*F)[3 * f + 1]], vi[(*F)[3 * f + 2]]);
    if (active.empty() || active[f]) faces.push_back(fi);
  }
  PMP::isotropic_remeshing(faces, h, m, CGAL::parameters::number_of_iterations(iterations));
  m.collect_garbage();
  V->clear();
  F->clear();
  for (auto v : m.vertices()) {
    const auto& p = m.point(v);
    V->insert(V->end(), {p.x(), p.y(), p.z()});
  }
  for (auto f : m.faces())
    for (auto v : CGAL::vertices_around_face(m.halfedge(f), m)) F->push_back(static_cast<int>(v));
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace arcs::bench
