// Time of every SDF -> mesh method on bunny_fixed (paper protocol: longest
// side 1, centred, SDF at linspace(-1, 1, n+1)^3) at n = 20, 40, 100, with
// marching cubes measured in the same run as the baseline. Median of `runs`
// runs (wall and process CPU seconds); the SDF sampling is not timed.
//
//   sdf_methods_bench [MESH] [--runs R] [--dcsdd-runs R] [--rfts-runs R] [--n 20,40,100] [--threads T]
//
// DCSDD runs its default 100 outer iterations (or until no vertex moves more
// than 1e-4 cell diagonals); `--dcsdd-runs` (default 1) limits its repeats.
// RFTS runs its flow at its defaults (seconds to minutes); `--rfts-runs`
// (default 1) limits its repeats.
// RFTA is timed by bench/rfta_bench (the paper's runtime figure).
#include "framework/context.h"
#include "framework/eval/metrics.h"
#include "framework/geometry/marching_cubes.h"
#include "framework/geometry/normalize.h"
#include "framework/io/mesh_io.h"
#include "framework/rfts/rfts.h"
#include "framework/sdf/sdf_sampling.h"
#include "framework/sdfmesh/dcsdd.h"
#include "framework/sdfmesh/dual_contouring.h"
#include "framework/sdfmesh/power_diagram.h"
#include "framework/sdfmesh/vdb_mesher.h"
#include "framework/util/parallel.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace {

using namespace arcs;

double CpuSeconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

struct Timing {
  double wall = 0, cpu = 0;
  Mesh mesh;  // of the last run
};

Timing Time(int runs, const std::function<Mesh()>& f) {
  std::vector<double> wall, cpu;
  Timing t;
  for (int r = 0; r < runs; ++r) {
    const double c0 = CpuSeconds();
    const auto w0 = std::chrono::steady_clock::now();
    t.mesh = f();
    wall.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count());
    cpu.push_back(CpuSeconds() - c0);
  }
  t.wall = Median(wall);
  t.cpu = Median(cpu);
  return t;
}

}  // namespace

int main(int argc, char** argv) {
  std::string mesh_path = ARCS_BENCH_DEFAULT_MESH;
  int runs = 3, dcsdd_runs = 1, rfts_runs = 1, threads = 0;
  std::vector<int> grids = {20, 40, 100};
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "%s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--runs") runs = std::max(1, std::atoi(next().c_str()));
    else if (a == "--dcsdd-runs") dcsdd_runs = std::max(1, std::atoi(next().c_str()));
    else if (a == "--rfts-runs") rfts_runs = std::max(1, std::atoi(next().c_str()));
    else if (a == "--threads") threads = std::atoi(next().c_str());
    else if (a == "--n") {
      grids.clear();
      std::string s = next();
      for (size_t p = 0; p < s.size();) {
        const size_t q = s.find(',', p);
        grids.push_back(std::atoi(s.substr(p, q - p).c_str()));
        p = q == std::string::npos ? s.size() : q + 1;
      }
    } else if (!a.empty() && a[0] != '-') mesh_path = a;
    else {
      std::fprintf(stderr, "usage: sdf_methods_bench [MESH] [--runs R] [--dcsdd-runs R] [--rfts-runs R] [--n 20,40,100] [--threads T]\n");
      return 2;
    }
  }
  if (!std::filesystem::exists(mesh_path)) {
    std::printf("sdf_methods_bench: %s not found (needs ../shared/data/bench/bunny_fixed.obj or a MESH argument); skipped\n",
                mesh_path.c_str());
    return 0;
  }
  ThreadLimit limit(threads);
  Mesh ref = ReadMesh(mesh_path);
  Normalize(&ref, NormalizeOptions{});
  std::printf("sdf_methods_bench: %s, %d threads, median of %d runs (DCSDD %d, RFTS %d); wall and CPU seconds, x = wall / MC's wall\n",
              std::filesystem::path(mesh_path).filename().c_str(), MaxThreads(), runs, dcsdd_runs, rfts_runs);
  std::printf("%5s  %-14s %10s %10s %10s %9s %9s\n", "n", "method", "wall_s", "cpu_s", "x_MC", "faces", "chamfer");
  for (int n : grids) {
    Context ctx(1);
    SdfGridOptions so;
    so.n = n;
    const SdfSamples s = SampleSdfGrid(ref, so, ctx);
    struct Method {
      std::string name;
      int runs;
      std::function<Mesh()> run;
      bool available;
    };
    const std::vector<Method> methods = {
        {"marching_cubes", runs, [&] { return MarchingCubes(s.values, *s.grid); }, true},
        {"dual_contouring", runs, [&] { return DualContouring(s.values, *s.grid); }, true},
        {"vdb_mesher", runs, [&] { return VdbVolumeToMesh(s.values, *s.grid); }, VdbMesherAvailable()},
        {"power_diagram", runs, [&] { return PowerDiagramContour(s); }, PowerDiagramAvailable()},
        {"dcsdd", dcsdd_runs, [&] { return Dcsdd(s, DcsddOptions{}, ctx); }, true},
        {"rfts", rfts_runs, [&] { return ReachForTheSpheres(s, RftsOptions{}, ctx).mesh; }, true},
    };
    double mc_wall = 0;
    for (const auto& m : methods) {
      if (!m.available) {
        std::printf("%5d  %-14s not built in\n", n, m.name.c_str());
        continue;
      }
      const Timing t = Time(m.runs, m.run);
      if (m.name == "marching_cubes") mc_wall = t.wall;
      const double chamfer = ChamferPaper(t.mesh, ref, 100000);
      std::printf("%5d  %-14s %10.4f %10.4f %10.1f %9d %9.5f\n", n, m.name.c_str(), t.wall, t.cpu,
                  mc_wall > 0 ? t.wall / mc_wall : 0.0, t.mesh.NumFaces(), chamfer);
      std::fflush(stdout);
    }
  }
  return 0;
}
