// CGAL AABB_tree closest-point back-end of spatial_bench (GPL code: benchmark only).
#include "bench_backends.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <chrono>
#include <thread>
#include <vector>

namespace arcs::bench {
namespace {
using K = CGAL::Simple_cartesian<double>;
using Triangle = K::Triangle_3;
using Iterator = std::vector<Triangle>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<K, Iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;
double Now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

double CgalClosestSqDists(const double* V, int nv, const int* F, int nf, const double* Q,
                          std::int64_t nq, int threads, double* out_sq, double* build_seconds) {
  const double t0 = Now();
  std::vector<Triangle> tris;
  tris.reserve(nf);
  auto P = [&](int i) { return K::Point_3(V[3 * i], V[3 * i + 1], V[3 * i + 2]); };
  for (int f = 0; f < nf; ++f) tris.emplace_back(P(F[3 * f]), P(F[3 * f + 1]), P(F[3 * f + 2]));
  Tree tree(tris.begin(), tris.end());
  tree.build();
  tree.accelerate_distance_queries();  // builds the internal kd-tree now, before threads
  const double t1 = Now();
  if (build_seconds) *build_seconds = t1 - t0;
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t) {
    pool.emplace_back([&, t] {
      const std::int64_t b = nq * t / threads, e = nq * (t + 1) / threads;
      for (std::int64_t i = b; i < e; ++i)
        out_sq[i] = CGAL::to_double(tree.squared_distance(K::Point_3(Q[3 * i], Q[3 * i + 1], Q[3 * i + 2])));
    });
  }
  for (auto& th : pool) th.join();
  return Now() - t1;
}

}  // namespace arcs::bench
