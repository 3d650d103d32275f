// Benchmark of the paper's evaluation protocol (issue: foundation, item 6).
// Prints, for a mesh (default bunny_fixed, 70k faces) at grid n (default 100,
// 1.03 M samples): SDF sampling time, marching-cubes time, and the time of
// one paper Chamfer at 10^6 samples per mesh — at 1 thread and at all cores.
// Targets on 2 cores: SDF sampling < 5 s, one Chamfer < 5 s.
//
//   protocol_bench [MESH] [n] [chamfer_samples]
#include "framework/context.h"
#include "framework/eval/metrics.h"
#include "framework/geometry/marching_cubes.h"
#include "framework/geometry/normalize.h"
#include "framework/io/mesh_io.h"
#include "framework/sdf/sdf_sampling.h"
#include "framework/util/parallel.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>

using namespace arcs;

namespace {
template <typename F>
double Time(F&& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

int main(int argc, char** argv) {
  const std::string path = argc > 1 ? argv[1] : ARCS_BENCH_DEFAULT_MESH;
  const int n = argc > 2 ? std::atoi(argv[2]) : 100;
  const std::int64_t samples = argc > 3 ? std::atoll(argv[3]) : 1000000;
  if (!std::filesystem::exists(path)) {
    std::fprintf(stderr, "protocol_bench: mesh %s not found (pass a mesh path as the first argument)\n", path.c_str());
    return 1;
  }
  Mesh mesh = ReadMesh(path);
  Normalize(&mesh, NormalizeOptions{});
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  std::printf("mesh %s: %d vertices, %d faces; grid n = %d (%lld samples); chamfer samples %lld; %d cores\n",
              path.c_str(), mesh.NumVertices(), mesh.NumFaces(), n, static_cast<long long>(n + 1) * (n + 1) * (n + 1),
              static_cast<long long>(samples), cores);
  std::printf("%-8s %14s %14s %14s %14s\n", "threads", "sdf_grid [s]", "mc [s]", "chamfer [s]", "chamfer");
  double t_sdf1 = 0, t_ch1 = 0;
  for (int threads : {1, cores}) {
    ThreadLimit limit(threads);
    Context ctx(1);
    SdfGridOptions o;
    o.n = n;
    SdfSamples s;
    const double t_sdf = Time([&] { s = SampleSdfGrid(mesh, o, ctx); });
    Mesh mc;
    const double t_mc = Time([&] { mc = MarchingCubes(s.values, *s.grid, 0.0); });
    double ch = 0;
    const double t_ch = Time([&] { ch = ChamferPaper(mc, mesh, samples, 1); });
    std::printf("%-8d %14.3f %14.3f %14.3f %14.6f\n", threads, t_sdf, t_mc, t_ch, ch);
    if (threads == 1) t_sdf1 = t_sdf, t_ch1 = t_ch;
    else
      std::printf("speed-up %d threads vs 1 (same run): sdf %.2fx, chamfer %.2fx\n", threads, t_sdf1 / t_sdf, t_ch1 / t_ch);
    if (cores == 1) break;
  }
  std::printf("targets (2 cores): sdf_grid < 5 s, chamfer < 5 s\n");
  return 0;
}
