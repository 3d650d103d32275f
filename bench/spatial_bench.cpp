// spatial_bench: speed of the spatial queries that dominate the RFTA protocol
// on one mesh (default: bunny_fixed from the workplace's shared data).
//
//   spatial_bench [MESH.obj] [--n 100] [--no-cgal] [--no-embree] [--no-exact]
//   spatial_bench MESH.obj --sign-check [--n 63]
//
// --sign-check only compares the inside/outside test of FastWindingNumber with
// the exact winding number on every node of the (n+1)^3 grid (exact sums for
// the nodes inside the bounding box, 0 outside it, which is exact for a closed
// mesh) and prints the number of disagreements.
//
// 1. Exact unsigned distance of the (n+1)^3 nodes of linspace(-1, 1, n+1)^3 to
//    the mesh normalised to a unit longest side centred at 0: our TriangleBvh
//    at 1 and 2 threads, CGAL AABB_tree (accelerate_distance_queries) and
//    Embree 3 rtcPointQuery when found at configure time; agreement (max abs
//    distance difference) and ratios against our BVH from the same run.
// 2. Inside/outside by FastWindingNumber on all nodes (1 and 2 threads) and
//    agreement with the exact winding number on a subset.
// 3. Nearest neighbours between two sets of 10^6 area-uniform surface samples,
//    both directions (the Chamfer distance of the paper).
#include "bench/bench_backends.h"
#include "framework/spatial/knn.h"
#include "framework/spatial/triangle_bvh.h"
#include "framework/spatial/winding_number.h"
#include "framework/util/parallel.h"
#include "framework/util/rng.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

namespace {

using arcs::Mesh;
using arcs::MatrixX3d;
using arcs::Vec3;
using arcs::VectorXd;

double Now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double Time(const std::function<void()>& f) {
  const double t0 = Now();
  f();
  return Now() - t0;
}

// Wall time, and the process CPU time in *cpu (on a shared machine the CPU
// time shows whether the second thread really got a core).
double Time(const std::function<void()>& f, double* cpu) {
  const std::clock_t c0 = std::clock();
  const double t = Time(f);
  *cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  return t;
}

// Minimal OBJ reader (v and f lines; polygons fan-triangulated).
bool ReadObj(const std::string& path, Mesh* m) {
  std::ifstream in(path);
  if (!in) return false;
  std::vector<double> v;
  std::vector<int> f;
  std::string line;
  while (std::getline(in, line)) {
    if (line.size() < 2 || (line[1] != ' ' && line[1] != '\t')) continue;
    std::istringstream s(line.substr(2));
    if (line[0] == 'v') {
      double x, y, z;
      s >> x >> y >> z;
      v.insert(v.end(), {x, y, z});
    } else if (line[0] == 'f') {
      std::string tok;
      std::vector<int> poly;
      const int nv = static_cast<int>(v.size() / 3);
      while (s >> tok) {
        const int i = std::atoi(tok.c_str());
        poly.push_back(i < 0 ? nv + i : i - 1);
      }
      for (std::size_t k = 1; k + 1 < poly.size(); ++k) f.insert(f.end(), {poly[0], poly[k], poly[k + 1]});
    }
  }
  m->V = Eigen::Map<MatrixX3d>(v.data(), v.size() / 3, 3);
  m->F = Eigen::Map<arcs::MatrixX3i>(f.data(), f.size() / 3, 3);
  return m->NumFaces() > 0;
}

void NormalizeUnitBox(Mesh* m) {
  const Vec3 lo = m->V.colwise().minCoeff().transpose(), hi = m->V.colwise().maxCoeff().transpose();
  const Vec3 c = 0.5 * (lo + hi);
  const double s = 1.0 / (hi - lo).maxCoeff();
  for (int i = 0; i < m->NumVertices(); ++i) m->V.row(i) = ((m->V.row(i).transpose() - c) * s).transpose();
}

MatrixX3d Grid(int n) {
  const int d = n + 1;
  MatrixX3d Q(static_cast<std::int64_t>(d) * d * d, 3);
  std::int64_t r = 0;
  for (int k = 0; k < d; ++k)
    for (int j = 0; j < d; ++j)
      for (int i = 0; i < d; ++i)
        Q.row(r++) << -1.0 + 2.0 * i / n, -1.0 + 2.0 * j / n, -1.0 + 2.0 * k / n;
  return Q;
}

// Area-uniform samples on the surface.
MatrixX3d SampleSurface(const Mesh& m, std::int64_t n, std::uint64_t seed) {
  std::vector<double> cum(m.NumFaces());
  double acc = 0.0;
  for (int f = 0; f < m.NumFaces(); ++f) {
    const Vec3 a = m.V.row(m.F(f, 0)), b = m.V.row(m.F(f, 1)), c = m.V.row(m.F(f, 2));
    acc += 0.5 * (b - a).cross(c - a).norm();
    cum[f] = acc;
  }
  arcs::Rng rng(seed);
  MatrixX3d P(n, 3);
  for (std::int64_t i = 0; i < n; ++i) {
    const double u = rng.Uniform() * acc;
    const int f = static_cast<int>(std::min<std::ptrdiff_t>(
        std::upper_bound(cum.begin(), cum.end(), u) - cum.begin(), m.NumFaces() - 1));
    double r1 = std::sqrt(rng.Uniform()), r2 = rng.Uniform();
    const Vec3 a = m.V.row(m.F(f, 0)), b = m.V.row(m.F(f, 1)), c = m.V.row(m.F(f, 2));
    P.row(i) = ((1 - r1) * a + r1 * (1 - r2) * b + r1 * r2 * c).transpose();
  }
  return P;
}

double MaxAbsDistDiff(const VectorXd& a, const VectorXd& b) {
  double m = 0.0;
  for (int i = 0; i < a.size(); ++i) m = std::max(m, std::abs(std::sqrt(a[i]) - std::sqrt(b[i])));
  return m;
}

// Indices of the grid nodes inside the mesh's bounding box.
std::vector<std::int64_t> NodesInBox(const Mesh& mesh, const MatrixX3d& Q) {
  const Vec3 lo = mesh.V.colwise().minCoeff().transpose(), hi = mesh.V.colwise().maxCoeff().transpose();
  std::vector<std::int64_t> in_box;
  for (std::int64_t i = 0; i < Q.rows(); ++i) {
    const Vec3 q = Q.row(i);
    if ((q.array() >= lo.array()).all() && (q.array() <= hi.array()).all()) in_box.push_back(i);
  }
  return in_box;
}

int SignCheck(const Mesh& mesh, int n, const std::string& path) {
  const MatrixX3d Q = Grid(n);
  const std::vector<std::int64_t> in_box = NodesInBox(mesh, Q);
  MatrixX3d Qb(in_box.size(), 3);
  for (std::size_t k = 0; k < in_box.size(); ++k) Qb.row(k) = Q.row(in_box[k]);
  VectorXd exact_box, fast;
  const double te = Time([&] { exact_box = arcs::WindingNumbersExact(mesh, Qb); });
  const double tf = Time([&] { fast = arcs::FastWindingNumber(mesh).Eval(Q); });
  VectorXd exact = VectorXd::Zero(Q.rows());
  for (std::size_t k = 0; k < in_box.size(); ++k) exact[in_box[k]] = exact_box[k];
  std::int64_t wrong = 0, inside = 0;
  double maxdw = 0.0;
  for (std::int64_t i = 0; i < Q.rows(); ++i) {
    wrong += (exact[i] > 0.5) != (fast[i] > 0.5);
    inside += exact[i] > 0.5;
    maxdw = std::max(maxdw, std::abs(exact[i] - fast[i]));
  }
  std::printf("sign check %s: %d faces, %lld nodes (%zu in the box, %lld inside): disagreements %lld, "
              "max |w_fast - w_exact| %.2e (exact %.1f s, fast %.3f s)\n",
              path.c_str(), mesh.NumFaces(), static_cast<long long>(Q.rows()), in_box.size(),
              static_cast<long long>(inside), static_cast<long long>(wrong), maxdw, te, tf);
  return wrong == 0 ? 0 : 3;
}

}  // namespace

int main(int argc, char** argv) {
  std::string path = ARCS_BENCH_DEFAULT_MESH;
  int n = 100;
  bool use_cgal = true, use_embree = true, use_exact = true, sign_check = false;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--n") && i + 1 < argc) {
      n = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--no-cgal")) {
      use_cgal = false;
    } else if (!std::strcmp(argv[i], "--no-embree")) {
      use_embree = false;
    } else if (!std::strcmp(argv[i], "--no-exact")) {
      use_exact = false;
    } else if (!std::strcmp(argv[i], "--sign-check")) {
      sign_check = true;
    } else if (argv[i][0] == '-') {
      std::fprintf(stderr,
                   "usage: %s [MESH.obj] [--n N] [--no-cgal] [--no-embree] [--no-exact] [--sign-check]\n",
                   argv[0]);
      return 2;
    } else {
      path = argv[i];
    }
  }
  if (!std::filesystem::exists(path)) {
    std::fprintf(stderr,
                 "spatial_bench: mesh not found: %s\n"
                 "  pass an OBJ file as the first argument (the default is the workplace's\n"
                 "  shared/data/bench/bunny_fixed.obj, absent in a plain clone).\n",
                 path.c_str());
    return 1;
  }
  Mesh mesh;
  if (!ReadObj(path, &mesh)) {
    std::fprintf(stderr, "spatial_bench: cannot read a triangle mesh from %s\n", path.c_str());
    return 1;
  }
  NormalizeUnitBox(&mesh);
  if (sign_check) return SignCheck(mesh, n, path);
  const MatrixX3d Q = Grid(n);
  std::printf("mesh %s: %d vertices, %d faces (normalised: longest side 1, centred)\n", path.c_str(),
              mesh.NumVertices(), mesh.NumFaces());
  std::printf("grid linspace(-1,1,%d)^3: %lld nodes; hardware threads %d\n\n", n + 1,
              static_cast<long long>(Q.rows()), arcs::MaxThreads());

  // ---- 1. closest points ----
  std::printf("== exact unsigned distance, %lld grid nodes ==\n", static_cast<long long>(Q.rows()));
  double t_build = 0;
  std::unique_ptr<arcs::TriangleBvh> bvh;
  t_build = Time([&] { bvh = std::make_unique<arcs::TriangleBvh>(mesh); });
  VectorXd d_ours1, d_ours2;
  double t1, t2, c1, c2;
  {
    arcs::ThreadLimit lim(1);
    t1 = Time([&] { bvh->ClosestPoints(Q, &d_ours1); }, &c1);
  }
  {
    arcs::ThreadLimit lim(2);
    t2 = Time([&] { bvh->ClosestPoints(Q, &d_ours2); }, &c2);
  }
  std::printf("  arcs TriangleBvh   build %.3f s | 1 thread %.3f s (cpu %.3f s, %.0f k q/s) | 2 threads %.3f s "
              "(cpu %.3f s) | 1 vs 2 threads identical: %s\n",
              t_build, t1, c1, Q.rows() / t1 / 1e3, t2, c2, d_ours1 == d_ours2 ? "yes" : "NO");
  std::vector<double> flatV(mesh.V.data(), mesh.V.data() + mesh.V.size());
  std::vector<int> flatF(mesh.F.data(), mesh.F.data() + mesh.F.size());
#ifdef ARCS_BENCH_HAVE_CGAL
  if (use_cgal) {
    VectorXd d(Q.rows());
    double build;
    double t = 0.0, cpu = 0.0;
    Time(
        [&] {
          t = arcs::bench::CgalClosestSqDists(flatV.data(), mesh.NumVertices(), flatF.data(), mesh.NumFaces(), Q.data(),
                                  Q.rows(), 1, d.data(), &build);
        },
        &cpu);
    // CPU-time ratio too: robust when the machine is shared.
    std::printf("  CGAL AABB_tree     build %.3f s | 1 thread %.3f s = %.1fx ours (cpu %.3f s = %.1fx ours) | "
                "max |d - d_ours| = %.3g\n",
                build, t, t / t1, cpu - build, (cpu - build) / c1, MaxAbsDistDiff(d, d_ours1));
  }
#else
  (void)use_cgal;
  std::printf("  CGAL AABB_tree     (not found at configure time)\n");
#endif
#ifdef ARCS_BENCH_HAVE_EMBREE
  if (use_embree) {
    VectorXd d(Q.rows());
    double build;
    double t = 0.0, cpu = 0.0;
    Time(
        [&] {
          t = arcs::bench::EmbreeClosestSqDists(flatV.data(), mesh.NumVertices(), flatF.data(), mesh.NumFaces(), Q.data(),
                                  Q.rows(), 1, d.data(), &build);
        },
        &cpu);
    // CPU-time ratio too: robust when the machine is shared.
    std::printf("  Embree rtcPointQuery build %.3f s | 1 thread %.3f s = %.1fx ours (cpu %.3f s = %.1fx ours) | "
                "max |d - d_ours| = %.3g\n",
                build, t, t / t1, cpu - build, (cpu - build) / c1, MaxAbsDistDiff(d, d_ours1));
  }
#else
  (void)use_embree;
  std::printf("  Embree 3           (not found at configure time)\n");
#endif

  // ---- 2. inside/outside ----
  std::printf("\n== sign by winding number ==\n");
  std::unique_ptr<arcs::FastWindingNumber> fwn;
  const double t_fbuild = Time([&] { fwn = std::make_unique<arcs::FastWindingNumber>(mesh); });
  VectorXd w1, w2;
  double s1, s2, sc1, sc2;
  {
    arcs::ThreadLimit lim(1);
    s1 = Time([&] { w1 = fwn->Eval(Q); }, &sc1);
  }
  {
    arcs::ThreadLimit lim(2);
    s2 = Time([&] { w2 = fwn->Eval(Q); }, &sc2);
  }
  std::printf("  FastWindingNumber (beta 2, order 2)  build %.3f s | 1 thread %.3f s (cpu %.3f s, %.0f k q/s) | "
              "2 threads %.3f s (cpu %.3f s) | identical: %s\n",
              t_fbuild, s1, sc1, Q.rows() / s1 / 1e3, s2, sc2, w1 == w2 ? "yes" : "NO");
  std::printf("  distance + sign, 2 threads: %.3f s (target < 5 s)\n", t2 + s2);
  if (use_exact) {
    // Nodes outside the bounding box have winding number exactly 0 for a
    // closed mesh; compare on a strided subset of the nodes inside it.
    const std::vector<std::int64_t> in_box = NodesInBox(mesh, Q);
    const std::int64_t want = 4000;
    const std::int64_t stride = std::max<std::int64_t>(1, static_cast<std::int64_t>(in_box.size()) / want);
    std::vector<std::int64_t> subset;
    for (std::size_t k = 0; k < in_box.size(); k += stride) subset.push_back(in_box[k]);
    MatrixX3d Qs(subset.size(), 3);
    for (std::size_t k = 0; k < subset.size(); ++k) Qs.row(k) = Q.row(subset[k]);
    VectorXd we;
    double te;
    {
      arcs::ThreadLimit lim(2);
      te = Time([&] { we = arcs::WindingNumbersExact(mesh, Qs); });
    }
    int wrong = 0, inside = 0;
    double maxdw = 0;
    for (std::size_t k = 0; k < subset.size(); ++k) {
      wrong += (we[k] > 0.5) != (w2[subset[k]] > 0.5);
      inside += we[k] > 0.5;
      maxdw = std::max(maxdw, std::abs(we[k] - w2[subset[k]]));
    }
    std::int64_t outside_wrong = 0;
    std::vector<char> in_subset_box(Q.rows(), 0);
    for (auto i : in_box) in_subset_box[i] = 1;
    for (std::int64_t i = 0; i < Q.rows(); ++i)
      if (!in_subset_box[i] && w2[i] > 0.5) ++outside_wrong;
    std::printf("  exact on %zu of the %zu nodes in the bounding box (%d inside): %.3f s on 2 threads "
                "(%.2e pairs/s) | sign disagreements %d | max |w_fast - w_exact| %.2e\n",
                subset.size(), in_box.size(), inside, te, double(subset.size()) * mesh.NumFaces() / te, wrong,
                maxdw);
    std::printf("  nodes outside the bounding box classified inside: %lld (exact: 0)\n",
                static_cast<long long>(outside_wrong));
  }

  // ---- 3. kNN for the Chamfer distance ----
  std::printf("\n== nearest neighbours, 10^6 x 10^6 surface samples (Chamfer) ==\n");
  const std::int64_t ns = 1000000;
  const MatrixX3d A = SampleSurface(mesh, ns, 1), B = SampleSurface(mesh, ns, 2);
  for (int threads : {1, 2}) {
    arcs::ThreadLimit lim(threads);
    Eigen::VectorXi ia, ib;
    VectorXd da, db;
    double tb = 0, tq = 0, cb = 0, cq = 0;
    tb += Time(
        [&] {
          arcs::KdTree3 ta(A), tbt(B);
          tq += Time(
              [&] {
                tbt.NearestBatch(A, &ia, &da);
                ta.NearestBatch(B, &ib, &db);
              },
              &cq);
        },
        &cb);
    const double chamfer = std::sqrt(da.mean()) + std::sqrt(db.mean());
    std::printf("  %d thread(s): build both %.3f s, query both directions %.3f s (cpu %.3f s), total %.3f s "
                "(cpu %.3f s) (Chamfer %.4g)\n",
                threads, tb - tq, tq, cq, tb, cb, chamfer);
  }
  return 0;
}
