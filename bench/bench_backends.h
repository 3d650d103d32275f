// Plain interfaces of the comparison back-ends of spatial_bench (each in its
// own translation unit so that CGAL/Embree headers stay out of the rest).
#pragma once

#include <cstdint>

namespace arcs::bench {

// Squared distance from each query to the triangle mesh (V: nv x 3 doubles,
// F: nf x 3 ints, row-major), `threads` std::threads over contiguous chunks.
// Returns the query time in seconds (excluding the build, reported in
// *build_seconds).
double CgalClosestSqDists(const double* V, int nv, const int* F, int nf, const double* Q,
                          std::int64_t nq, int threads, double* out_sq, double* build_seconds);
double EmbreeClosestSqDists(const double* V, int nv, const int* F, int nf, const double* Q,
                            std::int64_t nq, int threads, double* out_sq, double* build_seconds);

}  // namespace arcs::bench
