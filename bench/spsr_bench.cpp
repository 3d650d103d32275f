// arcs' own screened Poisson (framework/reconstruct/spsr.h) beside
// PoissonRecon 12 itself (Open3D 0.16, FEM degree 1, Neumann, weight fixed at
// 2) and PCL's port, on the same oriented points at the official RFTA
// geometry (depth 10, cube 3.2x the cloud, 1.5 samples per node). Prints, per
// cloud and back-end: wall and CPU seconds, vertices, components/genus, the
// Chamfer (point-to-surface) against the true surface, and against
// PoissonRecon's mesh. Weight 2 (PoissonRecon units) for every back-end, so
// ours and PoissonRecon solve the same energy; then ours at the official 10,
// and ours with each solver of the levels above the complete one
// (SpsrOptions::FineSolver) against the default cg_jacobi.
//
//   spsr_bench [REPEATS]   (default 3; medians are printed)
#include "framework/context.h"
#include "framework/eval/metrics.h"
#include "framework/geometry/builtin_shapes.h"
#include "framework/geometry/surface_sampling.h"
#include "framework/reconstruct/poisson.h"
#include "framework/reconstruct/spsr.h"
#include "framework/spatial/topology.h"
#include "framework/util/rng.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <cstdlib>
#include <functional>
#include <span>
#include <utility>
#include <string>
#include <vector>

using namespace arcs;

namespace {

PointCloud Cloud(const Mesh& t, int n, double noise, std::uint64_t seed) {
  PointCloud pc;
  Eigen::VectorXi face;
  pc.P = SampleSurfaceUniform(t, n, seed, &face);
  pc.N.resize(n, 3);
  Rng rng(seed + 1);
  for (int i = 0; i < n; ++i) {
    const Vec3 a = t.V.row(t.F(face[i], 0)), b = t.V.row(t.F(face[i], 1)), c = t.V.row(t.F(face[i], 2));
    pc.N.row(i) = (b - a).cross(c - a).normalized();
    pc.P.row(i) += noise * Eigen::RowVector3d(rng.Normal(), rng.Normal(), rng.Normal());
  }
  return pc;
}

struct Timed {
  Mesh mesh;
  double wall = 0, cpu = 0;
};

Timed Time(int repeats, const std::function<Mesh()>& f) {
  std::vector<double> w, c;
  Timed t;
  for (int r = 0; r < repeats; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::clock_t c0 = std::clock();
    t.mesh = f();
    c.push_back(double(std::clock() - c0) / CLOCKS_PER_SEC);
    w.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(w.begin(), w.end());
  std::sort(c.begin(), c.end());
  t.wall = w[w.size() / 2];
  t.cpu = c[c.size() / 2];
  return t;
}

void Row(const char* name, const Timed& t, const Mesh& truth, const Mesh* pr) {
  const Topology top = ComputeTopology(t.mesh);
  std::printf("  %-22s %7.3f %7.3f %8d %5d %5d %10.6f %10s\n", name, t.wall, t.cpu, t.mesh.NumVertices(),
              top.components, top.genus, ChamferPointToSurface(t.mesh, truth, 100000, 1),
              pr ? std::to_string(ChamferPointToSurface(t.mesh, *pr, 100000, 1)).c_str() : "-");
  std::fflush(stdout);
}

void Compare(const std::string& name, const PointCloud& pc, const Mesh& truth, int repeats) {
  Context ctx(1);
  std::printf("%s (%d points)\n  %-22s %7s %7s %8s %5s %5s %10s %10s\n", name.c_str(), pc.Size(), "back-end",
              "wall_s", "cpu_s", "verts", "comp", "genus", "chamfer", "vs_PR12");
  PoissonOptions o = OfficialRftaPoisson();  // the official geometry; back-end and weight set below
  o.backend = PoissonOptions::Backend::kPcl;
  o.point_weight = 2;
  const Mesh* pr = nullptr;
  Timed ref;
  if (PoissonOpen3dAvailable()) {
    PoissonOptions po = o;
    po.backend = PoissonOptions::Backend::kOpen3d;
    ref = Time(repeats, [&] { return ReconstructPoisson(pc, po, ctx); });
    pr = &ref.mesh;
    Row("PoissonRecon12 w2", ref, truth, nullptr);
  }
  if (PoissonAvailable()) Row("PCL w2 (area-norm.)", Time(repeats, [&] { return ReconstructPoisson(pc, o, ctx); }), truth, pr);
  const double expo = std::getenv("SPSR_EXPONENT") ? std::atof(std::getenv("SPSR_EXPONENT")) : 1.0;
  for (double w : {2.0, 10.0}) {
    SpsrOptions so;
    so.point_weight = w;
    so.screen_depth_exponent = expo;
    SpsrInfo info;
    const Timed t = Time(repeats, [&] { return ReconstructSpsr(pc, so, ctx, nullptr, &info); });
    Row(w == 2.0 ? "arcs spsr w2" : "arcs spsr w10", t, truth, pr);
    std::printf("    (depth %d, %lld unknowns, %d CG steps, solve %.3f s, extract %.3f s, area %.4f)\n", info.depth,
                info.unknowns, info.cg_iterations, info.solve_s, info.extract_s, info.area);
  }
  // The solvers above the complete level at the official weight, each against
  // cg_jacobi (the default) in this run: solve time (median of the repeats),
  // steps or sweeps, the finest level's relative residual, and the distance
  // between the surfaces.
  std::printf("  fine-level solvers, weight 10: %-16s %8s %7s %7s %10s %10s %10s\n", "solver", "solve_s", "ratio",
              "steps", "residual", "chamfer", "vs_cg_jac");
  Mesh base;
  double base_solve = 0;
  for (auto [solver, gs] : {std::pair{SpsrOptions::FineSolver::kCgJacobi, 8},
                            std::pair{SpsrOptions::FineSolver::kCgGaussSeidel, 8},
                            std::pair{SpsrOptions::FineSolver::kGaussSeidel, 8},
                            std::pair{SpsrOptions::FineSolver::kGaussSeidel, 16}}) {
    SpsrOptions so;
    so.fine_solver = solver;
    so.gs_iters = gs;
    SpsrInfo info;
    std::vector<double> solve;
    Mesh m;
    for (int r = 0; r < repeats; ++r) {
      m = ReconstructSpsr(pc, so, ctx, nullptr, &info);
      solve.push_back(info.solve_s);
    }
    std::sort(solve.begin(), solve.end());
    const double med = solve[solve.size() / 2];
    if (solver == SpsrOptions::FineSolver::kCgJacobi) {
      base = m;
      base_solve = med;
    }
    std::string label = EnumToName(kSpsrFineSolverNames, solver);
    if (solver == SpsrOptions::FineSolver::kGaussSeidel) label += " x" + std::to_string(gs);
    std::printf("  %-47s %8.3f %7.3f %7d %10.2e %10.6f %10.6f\n", label.c_str(), med, med / base_solve,
                info.cg_iterations, info.final_residual, ChamferPointToSurface(m, truth, 100000, 1),
                ChamferPointToSurface(m, base, 100000, 1));
    std::fflush(stdout);
  }
}

}  // namespace

int main(int argc, char** argv) {
  const int repeats = argc > 1 ? std::max(1, std::atoi(argv[1])) : 3;
  const Mesh torus = MakeTorus();
  Compare("torus, 5000 points, noise 0.01", Cloud(torus, 5000, 0.01, 5), torus, repeats);
  Compare("torus, 600 exact points", Cloud(torus, 600, 0.0, 9), torus, repeats);
  Compare("torus, 20000 exact points", Cloud(torus, 20000, 0.0, 3), torus, repeats);
  return 0;
}
