// Graph Voronoi at full resolution (framework/points/graph_voronoi_full.h)
// on the bunny (bun_zipper.ply, 35 947 points) and the merged dragon_stand
// scans (469 193 points): median wall and CPU time of the coarse
// reconstruction (the baseline, measured in the same run) and of the
// refinement that brings every point in, the share of input points that are
// vertices, and the topology of both meshes; beside CoCone's published times
// (Dumitriu et al., Table 1: one Pentium 4 core; CoCone keeps every point).
//
//   graph_voronoi_full_bench [--threads T] [--repeat R] [--out-dir DIR] [FILE...]
// --out-dir writes each mesh as DIR/<name>_full.ply and DIR/<name>_coarse.ply.
#include "framework/io/mesh_io.h"
#include "framework/io/points_io.h"
#include "framework/points/graph_voronoi.h"
#include "framework/points/graph_voronoi_full.h"
#include "framework/spatial/topology.h"
#include "framework/util/parallel.h"

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

using namespace arcs;

namespace {

double CpuNow() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return ru.ru_utime.tv_sec + ru.ru_stime.tv_sec + 1e-6 * (ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
}
double Now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }
double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

// Dumitriu et al., Table 1 (total incl. reading, and CoCone's time, seconds).
struct PaperRow { const char* model; int points; double gv_total, cocone; };
const PaperRow kPaper[] = {{"Bunny", 35947, 5.79, 29}, {"Dragon", 435545, 72.99, 761}};

}  // namespace

int main(int argc, char** argv) {
  int threads = 0, repeat = 3;
  std::string out_dir;
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if ((a == "--threads" || a == "--repeat" || a == "--out-dir") && i + 1 >= argc) {
      std::fprintf(stderr, "%s needs a value\n", a.c_str());
      return 2;
    }
    if (a == "--threads") threads = std::atoi(argv[++i]);
    else if (a == "--repeat") repeat = std::max(1, std::atoi(argv[++i]));
    else if (a == "--out-dir") out_dir = argv[++i];
    else if (a.rfind("--", 0) == 0) {
      std::fprintf(stderr, "unknown option %s\n", a.c_str());
      return 2;
    } else files.push_back(a);
  }
  std::string shared = ARCS_SHARED_DIR;
  if (const char* env = std::getenv("ARCS_SHARED_DIR")) shared = env;
  if (files.empty())
    files = {shared + "/data/scans/stanford_bunny_range/bun_zipper.ply",
             shared + "/data/scans/stanford_dragon_stand_range/dragon_stand_merged_registered.ply"};
  ThreadLimit limit(threads);
  std::printf("graph_voronoi_full_bench: %d thread(s), median of %d runs (wall / CPU seconds)\n", MaxThreads(), repeat);
  for (const auto& f : files) {
    if (!std::filesystem::exists(f)) {
      std::printf("%s: missing (skipped)\n", f.c_str());
      continue;
    }
    const PointCloud pc = ReadPointCloud(f);
    std::vector<double> cw, cc, fw, fc;
    GraphVoronoiResult coarse;
    Mesh full;
    FullResolutionStats fs;
    for (int r = 0; r < repeat; ++r) {
      double w0 = Now(), c0 = CpuNow();
      coarse = ReconstructGraphVoronoi(pc.P);
      cw.push_back(Now() - w0);
      cc.push_back(CpuNow() - c0);
      w0 = Now(), c0 = CpuNow();
      full = RefineGraphVoronoi(pc.P, coarse, {}, &fs);
      fw.push_back(Now() - w0);
      fc.push_back(CpuNow() - c0);
    }
    const Topology tc = ComputeTopology(coarse.mesh), tf = ComputeTopology(full);
    const std::string name = std::filesystem::path(f).stem().string();
    std::printf("%s: %lld points\n", name.c_str(), static_cast<long long>(pc.P.rows()));
    std::printf("  coarse (baseline)   wall %.3f  CPU %.3f   %d vertices (%.2f %% of points), %d triangles, "
                "closed %d, manifold %d, genus %d, components %d\n",
                Median(cw), Median(cc), tc.referenced_vertices, 100.0 * tc.referenced_vertices / pc.P.rows(),
                tc.faces, tc.closed, tc.manifold, tc.genus, tc.components);
    std::printf("  + full resolution   wall %.3f  CPU %.3f   (refinement alone: wall %.3f, CPU %.3f)\n",
                Median(cw) + Median(fw), Median(cc) + Median(fc), Median(fw), Median(fc));
    std::printf("  full-resolution mesh: %d vertices (%.2f %% of points), %d triangles, closed %d, manifold %d, "
                "genus %d, components %d; inserted %lld inside faces, %lld on edges; %lld merged (same "
                "position), %lld dropped (site in no face); %lld Delaunay flips; %lld folded triangles (%.2f %%)\n",
                tf.referenced_vertices, 100.0 * tf.referenced_vertices / pc.P.rows(), tf.faces, tf.closed,
                tf.manifold, tf.genus, tf.components, static_cast<long long>(fs.interior_points),
                static_cast<long long>(fs.edge_points), static_cast<long long>(fs.merged_points),
                static_cast<long long>(fs.dropped_points), static_cast<long long>(fs.flips),
                static_cast<long long>(fs.folded_triangles),
                tf.faces ? 100.0 * fs.folded_triangles / tf.faces : 0.0);
    if (!out_dir.empty()) {
      std::filesystem::create_directories(out_dir);
      WriteMesh((std::filesystem::path(out_dir) / (name + "_full.ply")).string(), full);
      WriteMesh((std::filesystem::path(out_dir) / (name + "_coarse.ply")).string(), coarse.mesh);
    }
  }
  std::printf("paper (Table 1; Pentium 4 3 GHz, one core; incl. reading the file):\n");
  for (const auto& p : kPaper)
    std::printf("  %-7s %7d points: graph Voronoi %.2f s (sites only), CoCone %.0f s (every point)\n", p.model,
                p.points, p.gv_total, p.cocone);
  return 0;
}
