// Benchmark of Reach for the Arcs against the official implementation's
// measured runs on this machine class (../shared/reference/official_rfta_measured.csv):
//   torus n=20 default preset (official 72 s, Chamfer 0.00390)
//   torus n=40 default preset (official 833 s, Chamfer 0.00176)
//   bunny_fixed n=20 paper preset (official 227 s, Chamfer 0.0219)
// "default" = gpytoolbox defaults (fine_tune_iters 3, max_points_per_sphere 3);
// "paper" = the paper's many-shapes runs (20 iterations, 30 points per sphere).
// Prints the wall time of each stage, the total, the paper's Chamfer (10^6
// samples) and the speed-up against the official wall time.
//
//   rfta_bench [all | torus20 | torus40 | bunny20]
#include "framework/context.h"
#include "framework/eval/metrics.h"
#include "framework/geometry/builtin_shapes.h"
#include "framework/geometry/normalize.h"
#include "framework/io/mesh_io.h"
#include "framework/sdf/sdf_sampling.h"
#include "framework/util/parallel.h"
#include "registry/registry.h"
#include "stages/builtin.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

using namespace arcs;

namespace {

struct BenchCase {
  std::string name, shape;
  int n, iterations, points_per_sphere;
  double official_wall_s, official_chamfer;
};

void Run(const BenchCase& bc, const Registry& registry) {
  Mesh mesh;
  if (bc.shape == "torus") {
    mesh = MakeTorus();
  } else {
    const std::string path = std::string(ARCS_SHARED_DIR) + "/data/bench/" + bc.shape + ".obj";
    if (!std::filesystem::exists(path)) {
      std::printf("%-10s skipped: %s not found\n", bc.name.c_str(), path.c_str());
      return;
    }
    mesh = ReadMesh(path);
  }
  Normalize(&mesh, NormalizeOptions{});
  Context ctx(1);
  SdfGridOptions go;
  go.n = bc.n;
  auto t0 = std::chrono::steady_clock::now();
  CaseData d;
  d.registry = &registry;
  d.samples = SampleSdfGrid(mesh, go, ctx);
  const double sdf_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ParamMap given;
  given.Set("iterations", static_cast<std::int64_t>(bc.iterations));
  given.Set("max_points_per_sphere", static_cast<std::int64_t>(bc.points_per_sphere));
  if (const char* td = std::getenv("RFTA_BENCH_TUNING_DEPTH")) {
    auto spec = std::make_shared<StageSpec>();
    spec->stage = "screened_poisson";
    spec->params.Set("depth", static_cast<std::int64_t>(std::atoi(td)));
    given.Set("tuning_reconstructor", spec);
  }
  const ParamMap params = registry.Resolve("rfta", given);
  t0 = std::chrono::steady_clock::now();
  registry.Get("rfta").factory(params)->Run(ctx, d);
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  auto metric = [&](const char* k) {
    for (const auto& [name, v] : d.metrics)
      if (name == k) return v;
    return 0.0;
  };
  const double chamfer = ChamferPaper(*d.output, mesh, 1000000, 1);
  std::printf("%-10s %6.2f %8.2f %8.2f %9.2f %8.2f %8.2f | %8.2f %9.0f %7.1fx | %9.5f %9.5f\n", bc.name.c_str(), sdf_s,
              metric("rfta_sampler_s"), metric("rfta_projector_s"), metric("rfta_fine_tune_s"),
              metric("fine_tune_reconstruct_s"), metric("rfta_final_s"), total, bc.official_wall_s,
              bc.official_wall_s / total, chamfer, bc.official_chamfer);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  const std::string which = argc > 1 ? argv[1] : "all";
  Registry registry;
  RegisterBuiltinStages(registry);
  const BenchCase cases[] = {
      {"torus20", "torus", 20, 3, 3, 72, 0.00390},
      {"torus40", "torus", 40, 3, 3, 833, 0.00176},
      {"bunny20", "bunny_fixed", 20, 20, 30, 227, 0.0219},
  };
  std::printf("RFTA vs the official implementation (its wall times measured on this machine class); %d threads\n",
              MaxThreads());
  std::printf("%-10s %6s %8s %8s %9s %8s %8s | %8s %9s %8s | %9s %9s\n", "case", "sdf", "sampler", "project",
              "finetune", "(psr)", "final", "total", "official", "speedup", "chamfer", "official");
  for (const auto& c : cases)
    if (which == "all" || which == c.name) Run(c, registry);
  return 0;
}
