// Benchmark of Reach for the Arcs against the official implementation's
// measured runs on this machine class (../shared/reference/official_rfta_measured.csv):
//   torus n=20 default preset (official 40.4 s on an unloaded machine, the
//   `default_quiet` row; the 72 s row was taken under load 3-9 and overstates
//   the official time ~1.8x; Chamfer 0.00390)
//   torus n=40 default preset (official 833 s, Chamfer 0.00176)
//   bunny_fixed n=20 paper preset (official 227 s, Chamfer 0.0219)
//   armadillo n=40 paper preset (no official run; issue 10's n = 40 target is
//   a median of 30 s over the bench set, where armadillo sits near the median)
// "default" = gpytoolbox defaults (fine_tune_iters 3, max_points_per_sphere 3);
// "paper" = the paper's many-shapes runs (20 iterations, 30 points per sphere).
// Prints the wall time of each stage, the total, the paper's Chamfer (10^6
// samples) and the speed-up against the official wall time, then where
// fine-tuning's time went (solves, surface queries, per-sphere updates).
// RFTA_BENCH_TUNING_EXTRACT_Q=Q: the tuning surfaces' extract_quantile
// (default 0.5, as the final mesh); RFTA_BENCH_TUNING_CG_ITERS=K
// their CG steps per level (default 40; only with a CG fine_solver, and
// since session 37 the default is gauss_seidel). RFTA_BENCH_FINE_SOLVER=cg_jacobi |
// cg_gauss_seidel | gauss_seidel and RFTA_BENCH_GS_ITERS=K: screened Poisson's
// solver above the complete level, for both surfaces (the stage's
// fine_solver and gs_iters). RFTA_BENCH_TUNING_CELL=F: rfta's tuning_cell (the
// tuning surfaces no finer than F x the samples' spacing; default 0 = off).
// RFTA_BENCH_BASE_ACCURACY=A: both surfaces' base_accuracy (the complete
// level's relative residual; default 1e-6).
//
//   rfta_bench [all | torus20 | torus40 | bunny20 | armadillo40]
//   rfta_bench scaling [SHAPE] [NMAX]
//   rfta_bench figure14 [NMAX [NMIN]]
//   rfta_bench carve [SHAPE [N [REPEATS]]]
// "figure14" is the paper's runtime figure itself (bunny_fixed, k_max 10,
// n_max 3, the paper's n = 5 ... 150 up to NMAX), each n beside the paper's
// time and the ratio ours / paper, with peak memory (see Figure14).
// "scaling" is the paper's Fig. 14: RFTA (default preset) on SHAPE (torus,
// or a bench mesh name) at n = 10 ... NMAX (default 100), printing per-stage
// wall time, peak resident memory of each run (reset before it), the number
// of samples N = (n+1)^3, and the growth exponent of the time between
// consecutive n (1 = linear in N; N log N gives slightly above 1).
// "carve" times what carving (RftaOptions::carve) adds to the final surface:
// RFTA's paper preset on SHAPE (default armadillo) at N (default 40) once,
// then the final screened Poisson on its points REPEATS times (default 5)
// with carving and without, interleaved (the field built inside the timed
// part, as the library builds it); prints the medians of wall and CPU time,
// the ratios on / off, and the meshes' sizes.
// Both run the library's ReachForTheArcs (framework/rfta/
// reach_for_the_arcs.h) with screened Poisson options; RFTA_BENCH_VIA=registry
// runs the registered `rfta` stage instead (the same result, tested in
// tests/stages/rfta_library_test.cpp).
#include "framework/context.h"
#include "framework/eval/metrics.h"
#include "orchestration/memory.h"
#include "framework/geometry/builtin_shapes.h"
#include "framework/geometry/normalize.h"
#include "framework/io/mesh_io.h"
#include "framework/rfta/reach_for_the_arcs.h"
#include "framework/rfta/sphere_carve.h"
#include "framework/sdf/sdf_sampling.h"
#include "framework/util/parallel.h"
#include "registry/registry.h"
#include "stages/builtin.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <span>
#include <string>
#include <utility>
#include <vector>

using namespace arcs;

namespace {

struct BenchCase {
  std::string name, shape;
  int n, iterations, points_per_sphere;
  double official_wall_s, official_chamfer;
};

// One RFTA run's output mesh and per-part wall times.
struct Outcome {
  Mesh mesh;
  double sampler_s = 0, projector_s = 0, fine_tune_s = 0, psr_s = 0, final_s = 0;
  double query_s = 0, update_s = 0;  // fine-tuning's surface queries and per-sphere updates (library path)
  double final_check_s = 0;          // fine-tuning's final check against all spheres (library path)
  std::int64_t points = 0;           // tangency points after the last iteration
  std::int64_t check_violators = 0, check_repaired = 0;  // the final check's counts (library path)
};

bool ViaRegistry() {
  const char* v = std::getenv("RFTA_BENCH_VIA");
  return v && std::string(v) == "registry";
}

// The environment's surface overrides (see Run) as Poisson options; false if none.
bool OfficialSurfaces(PoissonOptions* o) {
  const char* sf = std::getenv("RFTA_BENCH_SURFACES");
  if (!sf || std::string(sf) != "official") return false;
  *o = OfficialRftaPoisson();
  o->backend = PoissonOptions::Backend::kPcl;  // RFTA_BENCH_BACKEND picks another
  if (const char* w = std::getenv("RFTA_BENCH_WEIGHT")) o->point_weight = std::atof(w);
  if (const char* q = std::getenv("RFTA_BENCH_EXTRACT_Q")) o->extract_quantile = std::atof(q);
  if (const char* it = std::getenv("RFTA_BENCH_CG_ITERS")) o->cg_iters = std::atoi(it);
  if (const char* be = std::getenv("RFTA_BENCH_BACKEND"))
    o->backend = EnumFromName(std::span<const EnumName<PoissonOptions::Backend>>(kPoissonBackendNames), be);
  return true;
}

// Through the library: no registry.
Outcome RunLibrary(const SdfSamples& samples, int iterations, int points_per_sphere, const Context& ctx) {
  RftaOptions o;
  o.fine_tune.iterations = iterations;
  o.fine_tune.max_points_per_sphere = points_per_sphere;
  if (const char* td = std::getenv("RFTA_BENCH_TUNING_DEPTH")) {
    o.tuning_poisson = PoissonOptions{};
    o.tuning_poisson.depth = std::atoi(td);
  }
  PoissonOptions official;
  if (OfficialSurfaces(&official)) o.poisson = o.tuning_poisson = official;
  if (const char* q = std::getenv("RFTA_BENCH_TUNING_EXTRACT_Q")) o.tuning_poisson.extract_quantile = std::atof(q);
  if (const char* it = std::getenv("RFTA_BENCH_TUNING_CG_ITERS")) o.tuning_poisson.cg_iters = std::atoi(it);
  if (const char* fs = std::getenv("RFTA_BENCH_FINE_SOLVER")) {
    // Both surfaces, as the stage's screened_poisson parameter would be set.
    const auto solver = EnumFromName(std::span<const EnumName<SpsrOptions::FineSolver>>(kSpsrFineSolverNames), fs);
    o.poisson.fine_solver = o.tuning_poisson.fine_solver = solver;
  }
  if (const char* tc = std::getenv("RFTA_BENCH_TUNING_CELL")) o.tuning_cell = std::atof(tc);
  if (const char* gi = std::getenv("RFTA_BENCH_GS_ITERS")) o.poisson.gs_iters = o.tuning_poisson.gs_iters = std::atoi(gi);
  if (const char* ba = std::getenv("RFTA_BENCH_BASE_ACCURACY"))
    o.poisson.base_accuracy = o.tuning_poisson.base_accuracy = std::atof(ba);
  RftaResult r = ReachForTheArcs(samples, o, ctx);
  Outcome out;
  out.mesh = std::get<Mesh>(std::move(r.surface));
  out.sampler_s = r.sampler_s;
  out.projector_s = r.projector_s;
  out.fine_tune_s = r.fine_tune_s;
  out.final_check_s = r.tuning.final_check_s;
  out.check_violators = r.tuning.final_infeasible_before;
  out.check_repaired = r.tuning.final_repaired;
  for (const auto& it : r.tuning.iterations) {
    out.psr_s += it.reconstruct_s;
    out.query_s += it.query_s;
    out.update_s += it.update_s;
    out.points = it.points;
  }
  out.final_s = r.final_s;
  return out;
}

// Through the registered `rfta` stage (RFTA_BENCH_VIA=registry).
Outcome RunStage(const Registry& registry, const SdfSamples& samples, int iterations, int points_per_sphere,
                 Context& ctx) {
  CaseData d;
  d.registry = &registry;
  d.samples = samples;
  ParamMap given;
  given.Set("iterations", static_cast<std::int64_t>(iterations));
  given.Set("max_points_per_sphere", static_cast<std::int64_t>(points_per_sphere));
  if (const char* td = std::getenv("RFTA_BENCH_TUNING_DEPTH")) {
    auto spec = std::make_shared<StageSpec>();
    spec->stage = "screened_poisson";
    spec->params.Set("depth", static_cast<std::int64_t>(std::atoi(td)));
    given.Set("tuning_reconstructor", spec);
  }
  PoissonOptions official;
  if (OfficialSurfaces(&official)) {
    auto spec = std::make_shared<StageSpec>();
    spec->stage = "screened_poisson";
    spec->params.Set("depth", static_cast<std::int64_t>(official.depth));
    spec->params.Set("scale", official.scale);
    spec->params.Set("samples_per_node", official.samples_per_node);
    spec->params.Set("point_weight", official.point_weight);
    spec->params.Set("area_normalized", official.area_normalized);
    spec->params.Set("open_retries", static_cast<std::int64_t>(official.open_retries));
    if (const char* be = std::getenv("RFTA_BENCH_BACKEND")) spec->params.Set("backend", std::string(be));
    given.Set("reconstructor", spec);
    given.Set("tuning_reconstructor", spec);
  }
  registry.Get("rfta").factory(registry.Resolve("rfta", given))->Run(ctx, d);
  auto metric = [&](const char* k) {
    for (const auto& [name, v] : d.metrics)
      if (name == k) return v;
    return 0.0;
  };
  Outcome out;
  out.mesh = std::move(*d.output);
  out.sampler_s = metric("rfta_sampler_s");
  out.projector_s = metric("rfta_projector_s");
  out.fine_tune_s = metric("rfta_fine_tune_s");
  out.psr_s = metric("fine_tune_reconstruct_s");
  out.final_s = metric("rfta_final_s");
  return out;
}

Outcome RunRfta(const Registry& registry, const SdfSamples& samples, int iterations, int points_per_sphere,
                Context& ctx) {
  return ViaRegistry() ? RunStage(registry, samples, iterations, points_per_sphere, ctx)
                       : RunLibrary(samples, iterations, points_per_sphere, ctx);
}

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
  const SdfSamples samples = SampleSdfGrid(mesh, go, ctx);
  const double sdf_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // RFTA_BENCH_TUNING_DEPTH=D: screened Poisson at depth D inside fine-tuning.
  // RFTA_BENCH_SURFACES=official: both surfaces (tuning and final) as the
  // official call makes them: depth 10 in a cube 3.2x the cloud, 1.5 samples
  // per node, PoissonRecon's point weight 10 (area-normalised), no re-solves;
  // RFTA_BENCH_BACKEND=open3d: Open3D's PoissonRecon 12 (weight fixed at 2).
  t0 = std::chrono::steady_clock::now();
  const Outcome o = RunRfta(registry, samples, bc.iterations, bc.points_per_sphere, ctx);
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double chamfer = ChamferPaper(o.mesh, mesh, 1000000, 1);
  if (std::isnan(bc.official_wall_s)) {
    std::printf("%-10s %6.2f %8.2f %8.2f %9.2f %8.2f %8.2f | %8.2f %9s %8s | %9.5f %9s %8d\n", bc.name.c_str(), sdf_s,
                o.sampler_s, o.projector_s, o.fine_tune_s, o.psr_s, o.final_s, total, "-", "-", chamfer, "-",
                o.mesh.NumVertices());
  } else {
    std::printf("%-10s %6.2f %8.2f %8.2f %9.2f %8.2f %8.2f | %8.2f %9.0f %7.1fx | %9.5f %9.5f %8d\n", bc.name.c_str(),
                sdf_s, o.sampler_s, o.projector_s, o.fine_tune_s, o.psr_s, o.final_s, total, bc.official_wall_s,
                bc.official_wall_s / total, chamfer, bc.official_chamfer, o.mesh.NumVertices());
  }
  if (!ViaRegistry())
    std::printf("%-10s fine-tuning: solves %.2f s, queries %.2f s, updates %.2f s, final check %.2f s; %lld points "
                "at the end\n",
                "", o.psr_s, o.query_s, o.update_s, o.final_check_s, static_cast<long long>(o.points));
  std::fflush(stdout);
}

Mesh LoadShape(const std::string& shape) {
  if (shape == "torus") return MakeTorus();
  const std::string path = std::string(ARCS_SHARED_DIR) + "/data/bench/" + shape + ".obj";
  if (!std::filesystem::exists(path)) throw Error("rfta_bench: " + path + " not found");
  return ReadMesh(path);
}

int Scaling(const Registry& registry, const std::string& shape, int nmax) {
  Mesh mesh = LoadShape(shape);
  Normalize(&mesh, NormalizeOptions{});
  std::printf("RFTA runtime scaling (paper Fig. 14), %s, default preset, %d threads\n", shape.c_str(), MaxThreads());
  std::printf("%5s %9s | %8s %8s %9s %8s | %8s %9s %7s | %9s\n", "n", "N", "sampler", "project", "finetune", "final",
              "total", "peak_MB", "exp", "chamfer");
  double prev_t = 0, prev_n = 0;
  for (int n : {10, 20, 30, 40, 60, 80, 100, 120}) {
    if (n > nmax) break;
    Context ctx(1);
    SdfGridOptions go;
    go.n = n;
    const SdfSamples samples = SampleSdfGrid(mesh, go, ctx);
    const double N = static_cast<double>(samples.Size());
    ResetPeakRss();
    const auto t0 = std::chrono::steady_clock::now();
    const FineTuneOptions defaults;
    const Outcome o = RunRfta(registry, samples, defaults.iterations, defaults.max_points_per_sphere, ctx);
    const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double peak_mb = PeakRssBytes() / 1048576.0;
    const double chamfer = ChamferPaper(o.mesh, mesh, 1000000, 1);
    const double expo = prev_t > 0 ? std::log(total / prev_t) / std::log(N / prev_n) : 0.0;
    std::printf("%5d %9.0f | %8.2f %8.2f %9.2f %8.2f | %8.2f %9.0f %7.2f | %9.5f\n", n, N, o.sampler_s,
                o.projector_s, o.fine_tune_s, o.final_s, total, peak_mb, expo, chamfer);
    std::fflush(stdout);
    prev_t = total;
    prev_n = N;
  }
  return 0;
}

}  // namespace

// The paper's runtime figure (Fig. 14): bunny_fixed, fine_tune_iters 10,
// max_points_per_sphere 3, n = 5 ... NMAX of the paper's n list, each beside
// the paper's RFTA time and Chamfer (../shared/reference/rfta_paper_runtime.csv,
// read back from the figure; the authors' Mac with a GPU rasterizer) and the
// ratio ours / paper (issue 10's target: <= 0.1 at every n), with the peak
// resident memory of each run.
int Figure14(const Registry& registry, int nmax, int nmin) {
  const std::string csv = std::string(ARCS_SHARED_DIR) + "/reference/rfta_paper_runtime.csv";
  std::FILE* f = std::fopen(csv.c_str(), "r");
  if (!f) {
    std::printf("figure14 skipped: %s not found\n", csv.c_str());
    return 0;
  }
  std::vector<std::pair<double, std::pair<double, double>>> paper;  // n^3 -> (seconds, chamfer)
  char line[512];
  while (std::fgets(line, sizeof line, f)) {
    char method[32];
    double n3, sec, ch;
    if (std::sscanf(line, "%31[^,],%lf,%lf,%lf", method, &n3, &sec, &ch) == 4 && std::string(method) == "RFTA")
      paper.push_back({n3, {sec, ch}});
  }
  std::fclose(f);
  Mesh mesh = LoadShape("bunny_fixed");
  Normalize(&mesh, NormalizeOptions{});
  std::printf("RFTA runtime, the paper's Fig. 14 (bunny_fixed, k_max 10, n_max 3), %d threads\n", MaxThreads());
  std::printf("%5s %9s | %8s %8s %9s %8s | %8s %9s | %9s %7s | %9s %9s\n", "n", "n^3", "sampler", "project",
              "finetune", "final", "total", "peak_MB", "paper_s", "ratio", "chamfer", "paper_ch");
  for (const auto& [n3, ref] : paper) {
    const int n = static_cast<int>(std::lround(std::cbrt(n3)));
    if (n > nmax) break;
    if (n < nmin) continue;
    Context ctx(1);
    SdfGridOptions go;
    go.n = n;
    const SdfSamples samples = SampleSdfGrid(mesh, go, ctx);
    ResetPeakRss();
    const auto t0 = std::chrono::steady_clock::now();
    const Outcome o = RunRfta(registry, samples, 10, 3, ctx);
    const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double peak_mb = PeakRssBytes() / 1048576.0;
    const double chamfer = ChamferPaper(o.mesh, mesh, 1000000, 1);
    std::printf("%5d %9.0f | %8.2f %8.2f %9.2f %8.2f | %8.2f %9.0f | %9.2f %7.3f | %9.5f %9.5f\n", n, n3, o.sampler_s,
                o.projector_s, o.fine_tune_s, o.final_s, total, peak_mb, ref.first, total / ref.first, chamfer,
                ref.second);
    if (!ViaRegistry())
      std::printf("%5s fine-tuning: solves %.2f s, queries %.2f s, updates %.2f s, final check %.2f s (%lld violators, "
                  "%lld repaired); %lld points at the end\n",
                  "", o.psr_s, o.query_s, o.update_s, o.final_check_s, static_cast<long long>(o.check_violators),
                  static_cast<long long>(o.check_repaired), static_cast<long long>(o.points));
    std::fflush(stdout);
  }
  return 0;
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n == 0 ? NAN : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

int Carve(const std::string& shape, int n, int repeats) {
  if (shape != "torus" && !std::filesystem::exists(std::string(ARCS_SHARED_DIR) + "/data/bench/" + shape + ".obj")) {
    std::printf("carve skipped: %s not found in %s/data/bench\n", shape.c_str(), ARCS_SHARED_DIR);
    return 0;
  }
  Mesh mesh = LoadShape(shape);
  Normalize(&mesh, NormalizeOptions{});
  Context ctx(1);
  SdfGridOptions go;
  go.n = n;
  const SdfSamples samples = SampleSdfGrid(mesh, go, ctx);
  RftaOptions o;
  o.fine_tune.iterations = 20;
  o.fine_tune.max_points_per_sphere = 30;
  o.carve = false;
  const RftaResult r = ReachForTheArcs(samples, o, ctx);
  std::printf("carving's cost in RFTA's final surface: %s n = %d, paper preset, %lld tangency points, %d threads\n",
              shape.c_str(), n, static_cast<long long>(r.points.P.rows()), MaxThreads());
  std::vector<double> wall[2], cpu[2];
  Mesh out[2];
  for (int rep = 0; rep < repeats; ++rep)
    for (int on = 0; on < 2; ++on) {
      const auto t0 = std::chrono::steady_clock::now();
      const std::clock_t c0 = std::clock();
      RftaOptions f = o;
      if (on)
        f.poisson.carve = OutsideSpheresCarve(samples, CarveMargin(samples, o.fine_tune.search.tol, o.carve_margin));
      out[on] = std::get<Mesh>(DefaultRftaReconstructor(3, f, /*tuning=*/false, ctx)(r.points));
      wall[on].push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      cpu[on].push_back(static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC);
    }
  for (int on = 0; on < 2; ++on)
    std::printf("  carve %-3s wall median %7.3f s (min %.3f, max %.3f)  CPU median %7.3f s  %d vertices\n",
                on ? "on" : "off", Median(wall[on]), *std::min_element(wall[on].begin(), wall[on].end()),
                *std::max_element(wall[on].begin(), wall[on].end()), Median(cpu[on]), out[on].NumVertices());
  std::printf("  on / off: wall %.3f, CPU %.3f (medians of %d interleaved repeats)\n", Median(wall[1]) / Median(wall[0]),
              Median(cpu[1]) / Median(cpu[0]), repeats);
  return 0;
}

int main(int argc, char** argv) {
  // As the arcs command does (orchestration/memory.h); RFTA_BENCH_GLIBC_FREE=1
  // leaves glibc's defaults, for the comparison.
  if (!std::getenv("RFTA_BENCH_GLIBC_FREE")) KeepFreedMemory();
  const std::string which = argc > 1 ? argv[1] : "all";
  Registry registry;
  RegisterBuiltinStages(registry);
  if (which == "figure14")
    return Figure14(registry, argc > 2 ? std::atoi(argv[2]) : 150, argc > 3 ? std::atoi(argv[3]) : 0);
  if (which == "carve")
    return Carve(argc > 2 ? argv[2] : "armadillo", argc > 3 ? std::atoi(argv[3]) : 40, argc > 4 ? std::atoi(argv[4]) : 5);
  if (which == "scaling")
    return Scaling(registry, argc > 2 ? argv[2] : "torus", argc > 3 ? std::atoi(argv[3]) : 100);
  const BenchCase cases[] = {
      {"torus20", "torus", 20, 3, 3, 40.4, 0.00390},  // default_quiet (unloaded); 72 s was under load
      {"torus40", "torus", 40, 3, 3, 833, 0.00176},
      {"bunny20", "bunny_fixed", 20, 20, 30, 227, 0.0219},
      {"armadillo40", "armadillo", 40, 20, 30, NAN, NAN},  // no official run
  };
  std::printf("RFTA vs the official implementation (its wall times measured on this machine class); %d threads\n",
              MaxThreads());
  std::printf("%-10s %6s %8s %8s %9s %8s %8s | %8s %9s %8s | %9s %9s\n", "case", "sdf", "sampler", "project",
              "finetune", "(psr)", "final", "total", "official", "speedup", "chamfer", "official");
  std::printf("(last column: vertices of the final mesh; the official's at bunny n = 20: 38k)\n");
  for (const auto& c : cases)
    if (which == "all" || which == c.name) Run(c, registry);
  return 0;
}
