// arcs reconstruct POINTS OUT --method RECONSTRUCTOR [--param k=v]...: a mesh
// from a point cloud file with any reconstructor stage (screened_poisson,
// graph_voronoi, ball_pivoting, alpha_shape, advancing_front, plugins').
//
// The points are moved into the unit frame the stages' defaults are tuned
// for (bounding box centred, longest side 1: the datasets' `normalize`), the
// method runs there, and the mesh is written back in the input's frame
// (--frame normalized keeps the unit frame and records the transform beside
// OUT). Normals are estimated with the estimate_normals stage when the
// method needs oriented points and the file has none (or always, with
// --estimate-normals).
#include "app/cli.h"
#include "app/commands.h"
#include "app/stage_params.h"
#include "framework/error.h"
#include "framework/geometry/normalize.h"
#include "framework/geometry/transform_file.h"
#include "framework/io/mesh_io.h"
#include "framework/io/npy.h"
#include "framework/io/points_io.h"
#include "framework/spatial/topology.h"
#include "framework/util/parallel.h"
#include "registry/registry.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

namespace arcs {
namespace {

namespace fs = std::filesystem;

std::string LowerExt(const std::string& path) {
  std::string e = fs::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return e;
}

// Reconstructors that need oriented points (normals are estimated for them).
const std::set<std::string> kNeedsNormals = {"screened_poisson", "ball_pivoting", "screened_poisson_2d"};

const std::set<std::string> kPointExtensions = {".ply", ".xyz", ".pwn", ".pcd"};

PointCloud ReadPointsFile(const std::string& path) {
  if (LowerExt(path) == ".npy") {
    const NpyArray a = ReadNpy(path);
    if (a.Ndim() != 2 || (a.shape[1] != 3 && a.shape[1] != 6))
      throw InputError(path, 0, "points .npy must have shape (N, 3) (x y z) or (N, 6) (x y z nx ny nz), got " +
                                    NpyShapeString(a.shape));
    if (a.shape[0] == 0) throw InputError(path, 0, "no points");
    PointCloud pc;
    const std::int64_t n = a.shape[0], c = a.shape[1];
    pc.P.resize(n, 3);
    if (c == 6) pc.N.resize(n, 3);
    for (std::int64_t i = 0; i < n; ++i)
      for (int k = 0; k < c; ++k) {
        const double v = a.data[i * c + k];
        if (!std::isfinite(v)) throw InputError(path, 0, "row " + std::to_string(i) + " has a non-finite value");
        (k < 3 ? pc.P(i, k) : pc.N(i, k - 3)) = v;
      }
    return pc;
  }
  PointReadReport rep;
  PointCloud pc = ReadPointCloud(path, &rep);
  for (const auto& w : rep.warnings) std::fprintf(stderr, "%s: warning: %s\n", path.c_str(), w.c_str());
  if (!rep.skipped_lines.empty())
    std::fprintf(stderr, "%s: warning: %zu malformed or non-finite line(s) skipped (first: line %ld)\n", path.c_str(),
                 rep.skipped_lines.size(), rep.skipped_lines.front());
  if (pc.Size() == 0) throw InputError(path, 0, "no points");
  return pc;
}

// "name=value" list -> the stage's resolved parameters (the schema decides each type).
ParamMap DecodeStageParams(const Registry& registry, const std::string& stage, const std::vector<std::string>& kvs,
                           const std::string& flag) {
  return registry.Resolve(stage, DecodeGivenParams(registry, stage, kvs, flag));
}

}  // namespace

bool IsPointReconstruction(const Registry& registry, const std::string& input, const std::string& method) {
  if (!method.empty()) {
    const StageInfo* s = registry.Find(method);
    return s && s->role == Role::kReconstructor;
  }
  return kPointExtensions.count(LowerExt(input)) > 0;
}

int CmdReconstructPoints(Registry& registry, int argc, char** argv) {
  const cli::Args a = cli::Parse(argc, argv, 2,
                                 {"--method", "--param", "--normals-param", "--seed", "--threads", "--points", "--frame"},
                                 {"--estimate-normals"});
  if (a.positional.size() != 2) cli::Usage("reconstruct needs INPUT (points) and OUT (mesh file)");
  const std::string in = a.positional[0], out = a.positional[1];
  const std::string method = a.Get("--method", "screened_poisson");
  const StageInfo& info = registry.Get(method);
  if (info.role != Role::kReconstructor)
    cli::Usage("--method " + method + " is a " + RoleName(info.role) + " stage; points need a reconstructor");
  const std::string frame = a.Get("--frame", "input");
  if (frame != "input" && frame != "normalized") cli::Usage("--frame must be input or normalized, got '" + frame + "'");
  // Formats by extension, checked before any work.
  const std::string oext = LowerExt(out);
  if (SupportedMeshExtensions().find(oext.empty() ? "?" : oext) == std::string::npos)
    throw InputError(out, 0, "unsupported mesh output extension '" + oext + "' (supported: " + SupportedMeshExtensions() + ")");
  const std::string iext = LowerExt(in);
  if (!kPointExtensions.count(iext) && iext != ".npy" && iext != ".txt")
    throw InputError(in, 0, "unsupported point-cloud extension '" + iext + "' (supported: .ply .xyz .pwn .txt .pcd .npy)");
  const ParamMap params = DecodeStageParams(registry, method, a.All("--param"), "--param");
  const bool estimate = a.Has("--estimate-normals");
  const ParamMap nparams = DecodeStageParams(registry, "estimate_normals", a.All("--normals-param"), "--normals-param");
  const int seed = a.Has("--seed") ? cli::ParseInt(a.Get("--seed"), "--seed") : 1;
  const int threads = a.Has("--threads") ? cli::ParseInt(a.Get("--threads"), "--threads") : 0;
  if (threads < 0) cli::Usage("--threads must be >= 0");

  PointCloud pc = ReadPointsFile(in);
  const Similarity t = NormalizeTransform(pc.P, NormalizeOptions{});
  ApplySimilarity(t, &pc.P);  // normals: no rotation, positive scale -> unchanged
  CaseData data;
  data.registry = &registry;
  const bool had_normals = pc.HasNormals();
  data.points = std::move(pc);
  Context ctx(static_cast<std::uint64_t>(seed));
  ctx.set_log([](LogLevel l, const std::string& m) {
    if (l >= LogLevel::kWarning) std::fprintf(stderr, "%s\n", m.c_str());
  });
  ThreadLimit limit(threads);
  const auto t0 = std::chrono::steady_clock::now();
  bool estimated = false;
  if (estimate || (!had_normals && kNeedsNormals.count(method))) {
    ParamMap np = nparams;
    if (estimate) np.Set("when", std::string("always"));
    registry.Get("estimate_normals").factory(np)->Run(ctx, data);
    estimated = true;
  }
  registry.Get(method).factory(params)->Run(ctx, data);
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!data.output || data.output->Empty()) throw Error(method + " produced an empty mesh");
  Mesh mesh = frame == "input" ? ApplyInverseSimilarity(t, *data.output) : *data.output;
  WriteMesh(out, mesh);
  if (frame == "normalized")
    WriteTransformSidecar(out, t, "written by arcs reconstruct --frame normalized from " + fs::path(in).filename().string());
  if (a.Has("--points")) {
    if (!data.points) throw Error(method + " left no points to write to " + a.Get("--points"));
    PointCloud p = *data.points;
    if (frame == "input") {
      const Similarity inv = t.Inverse();
      ApplySimilarity(inv, &p.P);
    }
    WritePointCloud(a.Get("--points"), p);
  }
  const Topology topo = ComputeTopology(mesh);
  std::fprintf(stderr, "%s: %d points%s -> %d vertices, %d faces (closed %d, genus %d, %d components) in %.2f s -> %s\n",
               method.c_str(), data.points ? data.points->Size() : 0,
               estimated ? " (normals estimated)" : (had_normals ? " with normals" : ""), topo.vertices, topo.faces,
               topo.closed, topo.genus, topo.components, secs, out.c_str());
  return 0;
}

}  // namespace arcs
