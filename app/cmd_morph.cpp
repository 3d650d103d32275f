// arcs morph SOURCE TARGET OUT: deform a source mesh (default: an icosphere)
// so that its soft occupancy matches a target's (Luo et al. §2.4; see
// framework/voxel/morph.h and docs/morphing.md).
#include "app/cli.h"
#include "app/mesh_input.h"
#include "app/commands.h"
#include "framework/context.h"
#include "framework/geometry/builtin_shapes.h"
#include "framework/geometry/normalize.h"
#include "framework/io/mesh_io.h"
#include "framework/io/sdf_io.h"
#include "framework/util/parallel.h"
#include "framework/voxel/morph.h"
#include "framework/voxel/voxelize.h"
#include "stages/voxel/voxel_params.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace arcs {

namespace {

constexpr const char* kMorphUsage =
    "morph SOURCE TARGET OUT [options]\n"
    "  SOURCE  'sphere' (an icosphere of the target's volume at its centroid), 'shape:NAME', or a mesh file\n"
    "          (fitted to the target's occupied bounding box)\n"
    "  TARGET  a mesh file or shape:NAME (normalised: longest side 1, centred; voxelised on --res^3 nodes over\n"
    "          [-0.55, 0.55]^3 by winding number > 0.5), or a 3D .npy occupancy grid (inside iff > 0.5;\n"
    "          numpy (nx, ny, nz) order, bounds from --bounds, its .bounds sidecar, or [-1, 1]^3)\n"
    "  OUT     the morphed mesh (in the target mesh's own frame, or the grid's frame for .npy)\n"
    "options: --seed N (1) --log CSV --threads T --bounds 'xmin ymin zmin xmax ymax zmax'\n"
    "the morph stage's parameters (`arcs describe morph`):\n";

// The morph stage's parameters as flags; refresh_every keeps its flag --every.
std::vector<cli::SchemaFlag> MorphFlags(const Registry& registry) {
  return cli::StageFlags(registry, "morph", {}, {{"refresh_every", "every"}});
}

[[noreturn]] void MorphUsage(const Registry& registry, const std::string& msg) {
  cli::Usage(msg + "\nusage: arcs " + kMorphUsage + cli::FlagHelp(MorphFlags(registry)));
}

bool EndsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

Mesh LoadMeshOrShape(const std::string& spec) {
  if (spec.rfind("shape:", 0) == 0) return MakeBuiltinShape(spec.substr(6));
  return cli::ReadMeshForCommand(spec);
}

}  // namespace

int CmdMorph(Registry& registry, int argc, char** argv) {
  const std::vector<cli::SchemaFlag> flags = MorphFlags(registry);
  for (int i = 2; i < argc; ++i)
    if (std::string(argv[i]) == "--help" || std::string(argv[i]) == "-h") {
      std::printf("usage: arcs %s%s", kMorphUsage, cli::FlagHelp(flags).c_str());
      return 0;
    }
  std::vector<std::string> with_value = cli::FlagNames(flags);
  for (const char* f : {"--seed", "--log", "--threads", "--bounds"}) with_value.push_back(f);
  const cli::Args a = cli::Parse(argc, argv, 2, with_value, {});
  if (a.positional.size() != 3) MorphUsage(registry, "morph needs SOURCE, TARGET and OUT");
  const std::string source_spec = a.positional[0], target_spec = a.positional[1], out = a.positional[2];

  // The stage's parameters: its bounds and MorphOptions::Check() through Registry::Resolve.
  const MorphStageOptions so = MorphParams().Decode(cli::ResolveStageFlags(registry, "morph", flags, a));
  const int res = so.res, subdiv = so.subdivisions;
  const MorphOptions& o = so.morph;
  const int threads = a.Has("--threads") ? cli::ParseInt(a.Get("--threads"), "--threads", 0, 4096) : 0;
  if (threads < 0) MorphUsage(registry, "--threads must be >= 0");
  const std::uint64_t seed = a.Has("--seed") ? static_cast<std::uint64_t>(cli::ParseInt64(a.Get("--seed"), "--seed", 0)) : 1;

  // A source file is read first: a bad file fails before the target is voxelised.
  Mesh source_file;
  if (source_spec != "sphere") source_file = LoadMeshOrShape(source_spec);
  // Target occupancy, and the map from the grid's frame back to the output frame.
  VolumeGrid target;
  Similarity to_out;  // identity
  const bool npy_target = EndsWith(target_spec, ".npy");
  std::array<double, 3> lo{-1, -1, -1}, hi{1, 1, 1};
  if (a.Has("--bounds")) {
    if (!npy_target) MorphUsage(registry, "--bounds applies to a .npy TARGET only");
    std::istringstream in(a.Get("--bounds"));
    for (double* v : {&lo[0], &lo[1], &lo[2], &hi[0], &hi[1], &hi[2]})
      if (!(in >> *v)) MorphUsage(registry, "--bounds needs six numbers 'xmin ymin zmin xmax ymax zmax'");
    for (int k = 0; k < 3; ++k)
      if (!(hi[k] > lo[k])) MorphUsage(registry, "--bounds: max must exceed min on every axis");
  }
  if (npy_target) {
    const SdfSamples s = ReadSdfGrid(target_spec, lo, hi);
    if (s.dim != 3 || !s.grid) throw Error(target_spec + ": a 3D occupancy grid (nx, ny, nz) is needed");
    target.info = *s.grid;
    target.values = s.values;
  } else {
    Mesh t = LoadMeshOrShape(target_spec);
    if (t.Empty()) throw Error(target_spec + ": the target mesh has no faces");
    const Similarity sim = cli::NormalizeForCommand(&t, NormalizeOptions{}, target_spec);
    to_out = sim.Inverse();
    target.info = CubeGrid(res, Vec3::Constant(-0.55), Vec3::Constant(0.55));
    target.values = HardOccupancy(t, target.info);
  }
  ThreadLimit limit(threads);
  Mesh source;
  if (source_spec == "sphere") {
    source = InitialSphere(target, subdiv);
  } else {
    source = FitSourceToTarget(source_file, target);
  }

  std::ofstream log;
  if (a.Has("--log")) {
    log.open(a.Get("--log"));
    if (!log) throw Error(a.Get("--log") + ": cannot write the log");
    log << "iteration,iou,loss,active_nodes,seconds\n";
  }
  std::printf("morph: %s -> %s: %d vertices, %d faces, %lld grid nodes, %d iterations\n", source_spec.c_str(),
              target_spec.c_str(), source.NumVertices(), source.NumFaces(),
              static_cast<long long>(target.info.NumNodes()), o.iterations);
  Context ctx(seed);
  const MorphResult r = MorphToOccupancy(source, target, o, ctx, [&](const MorphLogEntry& e) {
    std::printf("iteration %5d  IoU %.4f  loss %.5f  active %7d  %7.2f s\n", e.iteration, e.iou, e.loss, e.active,
                e.seconds);
    std::fflush(stdout);
    if (log.is_open()) {
      char line[256];
      std::snprintf(line, sizeof line, "%d,%.6f,%.8g,%d,%.3f\n", e.iteration, e.iou, e.loss, e.active, e.seconds);
      log << line << std::flush;
    }
  });
  WriteMesh(out, ApplySimilarity(to_out, r.mesh));
  std::printf("morph: IoU %.4f -> %.4f after %d iterations in %.2f s -> %s\n", r.initial_iou, r.final_iou,
              r.iterations, r.seconds, out.c_str());
  return 0;
}

}  // namespace arcs
