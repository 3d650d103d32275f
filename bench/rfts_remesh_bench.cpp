// The remesher of RFTS: ours (framework/rfts/remesh.h, Botsch–Kobbelt on a
// patch) against CGAL's isotropic_remeshing (when built with CGAL), one
// round per call as the flow does, on icospheres of the sizes the flow sees,
// the whole mesh and a 10 % patch. Prints the median of `runs` calls (wall
// and CPU) per case.
//   rfts_remesh_bench [runs=5]
#include "framework/geometry/builtin_shapes.h"
#include "framework/rfts/remesh.h"
#include "framework/spatial/topology.h"

#ifdef ARCS_BENCH_HAVE_CGAL
#include "rfts_remesh_backend.h"
#endif

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <vector>

using namespace arcs;

namespace {
double Cpu() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }
double Wall() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}
// A bumpy sphere so that the remesher has work: radius modulated by angle.
Mesh Bumpy(int subdivisions) {
  Mesh m = MakeIcosphere(1.0, subdivisions);
  for (int v = 0; v < m.NumVertices(); ++v) {
    const Vec3 p = m.V.row(v);
    m.V.row(v) *= 1.0 + 0.1 * std::sin(5 * p.x()) * std::cos(4 * p.y());
  }
  return m;
}
}  // namespace

int main(int argc, char** argv) {
  const int runs = argc > 1 ? std::max(1, std::atoi(argv[1])) : 5;
  std::printf("%-10s %-6s %-7s %-6s %12s %12s %10s\n", "faces", "patch", "method", "h", "wall_s(med)", "cpu_s(med)",
              "out_faces");
  for (int sub : {3, 4, 5}) {
    const Mesh base = Bumpy(sub);


    const double h = 1.05 / (1 << sub);  // about the input edge length: the steady state of the flow
    for (bool patch : {false, true}) {
      std::vector<char> active;
      if (patch) {
        active.assign(base.NumFaces(), 0);
        for (int f = 0; f < base.NumFaces(); ++f) active[f] = base.V(base.F(f, 0), 2) > 0.8;
      }
      std::vector<double> w, c;
      int out = 0;
      for (int r = 0; r < runs; ++r) {
        Mesh m = base;
        const double w0 = Wall(), c0 = Cpu();
        RemeshOptions o;
        o.target_edge_length = h;
        RemeshPatch(&m, active, o);
        w.push_back(Wall() - w0);
        c.push_back(Cpu() - c0);
        out = m.NumFaces();
        if (!ComputeTopology(m).manifold) std::printf("  ours: not manifold!\n");
      }
      std::printf("%-10d %-6s %-7s %-6.3f %12.5f %12.5f %10d\n", base.NumFaces(), patch ? "10%" : "all", "ours", h,
                  Median(w), Median(c), out);
#ifdef ARCS_BENCH_HAVE_CGAL
      w.clear();
      c.clear();
      for (int r = 0; r < runs; ++r) {
        std::vector<double> V(base.V.data(), base.V.data() + base.V.size());
        std::vector<int> F(base.F.data(), base.F.data() + base.F.size());
        const double w0 = Wall(), c0 = Cpu();
        bench::CgalIsotropicRemesh(&V, &F, active, h, 1);
        w.push_back(Wall() - w0);
        c.push_back(Cpu() - c0);
        out = static_cast<int>(F.size() / 3);
      }
      std::printf("%-10d %-6s %-7s %-6.3f %12.5f %12.5f %10d\n", base.NumFaces(), patch ? "10%" : "all", "CGAL", h,
                  Median(w), Median(c), out);
#endif
    }
  }
  return 0;
}
