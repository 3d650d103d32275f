// arcs: one binary with subcommands (run | list | describe | table | sdf | eval | version).
#include "framework/eval/metrics.h"
#include "orchestration/csv.h"
#include "orchestration/memory.h"
#include "orchestration/spec.h"
#include "orchestration/results_dir.h"
#include "orchestration/runner.h"
#include "orchestration/tables.h"
#include "orchestration/version.h"
#include "framework/geometry/builtin_shapes.h"
#include "framework/geometry/normalize.h"
#include "framework/geometry/transform_file.h"
#include "framework/io/mesh_io.h"
#include "framework/io/points_io.h"
#include "framework/geometry/curves.h"
#include "framework/sdf/sdf2d.h"
#include "framework/io/sdf_io.h"
#include "framework/sdf/sdf_sampling.h"
#include "framework/spatial/topology.h"
#include "framework/util/parallel.h"
#include "registry/plugin.h"
#include "registry/plugin_api.h"
#include "stages/builtin.h"
#include "app/cli.h"
#include "app/mesh_input.h"
#include "app/commands.h"
#include "app/stage_params.h"

#include <chrono>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <unistd.h>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace arcs;
using namespace arcs::cli;

namespace {

const char* kUsage = R"(arcs — surfaces from signed distances and point clouds, and how well it went

usage: arcs <command> [options]

commands:
  run EXP.yaml [--set path.to.param=value]... [--jobs N] [--threads T] [--out DIR]
               [--retry-failed] [--no-isolate] [--quiet] [--save-outputs]
               [--shard I/N] [--dry-run]
                             expand the experiment into cases and run them; resumes;
                             --save-outputs: each case's mesh/curve/points into DIR/outputs/
                             --shard I/N: only shard I of N (default: a Slurm array task's);
                             --dry-run: list the cases (and their count), run nothing
  slurm EXP.yaml --array N --out DIR [options] [--submit]
                             an sbatch job array running the shards, and the table job
                             (`arcs slurm --help`)
  table RESULTS_DIR [--tables EXP.yaml]
                             rebuild the tables from RESULTS_DIR's results files
  list                       every registered stage, by role
  describe STAGE             a stage's parameters with defaults, ranges and docs
  sdf MESH OUT [--n N] [--random COUNT] [--no-normalize] [--rotate SEED] [--curve] [--threads T]
                             sample a mesh's SDF (paper protocol) to OUT (.npy, .npz, .txt);
                             --curve: MESH is a 2D polyline file or built-in curve name
  eval MESH REFERENCE [--samples N] [--sdf FILE] [--frame reference|each|none] [--json]
                             the paper's metrics of MESH against REFERENCE, in one frame
  reconstruct INPUT OUT [--method STAGE] [--param name=value]... [--points PTS.ply]
                             SDF samples (grid .npy, (N,d+1) .npy, .npz, text) -> mesh OUT with
                             an sdf_to_mesh stage (rfta (default), marching_cubes, ...), or
                             points (.ply .xyz .pcd .npy) with a reconstructor (screened_poisson
                             (default for point files), graph_voronoi, ball_pivoting, ...)
  shape NAME OUT             write a built-in shape (sphere, torus, knot, two_tori), or a
                             built-in 2D curve as a polyline (.obj/.txt/.svg; `arcs shape list`)
  voxelize MESH OUT.npy [options]
                             winding-number occupancy grid of MESH (`arcs voxelize --help`)
  morph SOURCE TARGET OUT [options]
                             deform SOURCE mesh to match TARGET's occupancy (`arcs morph --help`)
  plot RESULTS_DIR [--figure runtime|scatter|ablation|voxel]... [--out DIR] [--formats png,pdf]
                             the papers' figures from results.csv (`arcs plot --help`)
  render MESH... --out IMAGE [--labels A,B,...]
                             meshes side by side, shaded, headless
  report RESULTS_DIR [--out FILE.html]
                             one self-contained HTML page: tables, figures, renders per case
  version                    version, build and plugin API (also: arcs --version)

`arcs COMMAND --help` lists a command's options (for reconstruct, with --method M: M's parameters).

global options (anywhere on the line):
  --plugin FILE              load a plugin (also: $ARCS_PLUGIN_PATH, or `plugins:` in YAML)
  --threads T                worker threads (default: all cores)
)";

void LoadPlugins(Registry& registry, const Args& args) {
  if (const char* path = std::getenv("ARCS_PLUGIN_PATH"))
    for (const auto& p : FindPlugins(path)) LoadPlugin(registry, p);
  for (const auto& p : args.All("--plugin")) LoadPlugin(registry, p);
}

int CmdList(const Registry& registry) {
  Role last = Role::kOther;
  bool first = true;
  for (const StageInfo* s : registry.List()) {
    if (first || s->role != last) {
      std::printf("%s%s:\n", first ? "" : "\n", RoleName(s->role));
      last = s->role;
      first = false;
    }
    std::printf("  %-22s %s%s\n", s->name.c_str(), s->doc.c_str(),
                s->origin == "builtin" ? "" : ("  [" + s->origin + "]").c_str());
  }
  return 0;
}

int CmdDescribe(const Registry& registry, const std::string& name) {
  const StageInfo& s = registry.Get(name);
  std::printf("%s  (role: %s, from: %s)\n  %s\n", s.name.c_str(), RoleName(s.role), s.origin.c_str(), s.doc.c_str());
  if (s.params.specs().empty()) {
    std::printf("\n  no parameters\n");
  } else {
    std::printf("\n  %-20s %-7s %-22s %-28s %s\n", "parameter", "type", "default", "allowed", "description");
    for (const auto& p : s.params.specs())
      std::printf("  %-20s %-7s %-22s %-28s %s\n", p.name.c_str(), ParamTypeName(p.type),
                  FormatParamValue(p.default_value).c_str(), p.RangeText().c_str(), p.doc.c_str());
  }
  if (!s.outputs.empty()) {
    std::string o;
    for (const auto& x : s.outputs) o += (o.empty() ? "" : ", ") + x;
    std::printf("\n  writes columns: %s\n", o.c_str());
  }
  return 0;
}

int WriteTablesFor(const std::vector<TableSpec>& specs, const std::string& dir, bool print,
                   const std::vector<std::string>& sources = {}) {
  std::vector<std::string> warnings;
  // results.csv and every shard's file of DIR, or the union of the sources.
  const CsvTable t = sources.empty() ? ReadResultsDir(dir, &warnings) : ReadResults(sources, &warnings);
  const auto tables = BuildTables(specs, t, &warnings);
  for (const auto& w : warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  const std::string md = WriteTables(tables, (fs::path(dir) / "tables").string());
  if (print) std::printf("%s", md.c_str());
  if (!tables.empty())
    std::fprintf(stderr, "tables written to %s/ (.md, .csv, .tex)\n", (fs::path(dir) / "tables").c_str());
  return 0;
}

int CmdRun(Registry& registry, const Args& args, int argc, char** argv) {
  if (args.positional.size() != 1) Usage("run needs exactly one experiment file");
  const Experiment exp = LoadExperiment(args.positional[0], args.All("--set"), registry);
  RunOptions o;
  o.out_dir = args.Get("--out", DefaultOutDir(exp));
  o.jobs = args.Has("--jobs") ? ParseInt(args.Get("--jobs"), "--jobs", 1, 4096) : 1;
  o.threads = args.Has("--threads") ? ParseInt(args.Get("--threads"), "--threads", 0, 4096) : 0;
  if (o.jobs < 1) Usage("--jobs must be >= 1");
  if (o.threads < 0) Usage("--threads must be >= 0");
  o.isolate = !args.Has("--no-isolate");
  o.retry_failed = args.Has("--retry-failed");
  o.save_outputs = args.Has("--save-outputs");
  o.progress = !args.Has("--quiet");
  o.shard = args.Has("--shard") ? ParseShard(args.Get("--shard")) : ShardFromEnvironment();
  if (args.Has("--dry-run")) return ListCases(exp, registry, o) >= 0 ? 0 : 1;
  for (int i = 0; i < argc; ++i) o.command_line.push_back(argv[i]);
  const RunSummary s = RunExperiment(exp, registry, o);
  if (o.shard.sharded())  // N writers' partial tables would race: the table job builds them from the union
    std::fprintf(stderr, "shard %s: tables with `arcs table %s` once every shard has run\n", o.shard.Text().c_str(), o.out_dir.c_str());
  else if (!exp.tables.empty()) WriteTablesFor(exp.tables, o.out_dir, !args.Has("--quiet"));
  std::fprintf(stderr, "results: %s/%s\n", o.out_dir.c_str(), ResultsFileName(o.shard).c_str());
  return s.interrupted ? 130 : 0;
}

int CmdTable(const Args& args) {
  if (args.positional.empty()) Usage("table needs a results directory");
  const std::string dir = args.positional[0];
  if (args.positional.size() == 1 && !args.Has("--out")) {
    const std::string spec_file = args.Get("--tables", (fs::path(dir) / "config.resolved.yaml").string());
    if (!fs::exists(spec_file)) throw Error(spec_file + ": not found (is " + dir + " a results directory?)");
    const auto specs = LoadTableSpecs(spec_file);
    if (specs.empty()) throw Error(spec_file + ": defines no tables");
    return WriteTablesFor(specs, dir, true);
  }
  // Several runs (directories or results .csv files) into one table.
  if (!args.Has("--tables")) Usage("table with several results (or --out) needs --tables EXP.yaml");
  if (!args.Has("--out")) Usage("table with several results needs --out DIR for the tables");
  const std::string spec_file = args.Get("--tables");
  if (!fs::exists(spec_file)) throw Error(spec_file + ": not found");
  const auto specs = LoadTableSpecs(spec_file);
  if (specs.empty()) throw Error(spec_file + ": defines no tables");
  const std::string out = args.Get("--out");
  fs::create_directories(out);
  return WriteTablesFor(specs, out, true, args.positional);
}

Mesh LoadMeshNormalized(const std::string& path, bool normalize, int rotate_seed, Similarity* applied = nullptr) {
  Mesh m = path.rfind("shape:", 0) == 0 ? MakeBuiltinShape(path.substr(6)) : ReadMeshForCommand(path);
  if (normalize) {
    NormalizeOptions no;
    if (rotate_seed >= 0) {
      no.random_rotation = true;
      no.rotation_seed = static_cast<std::uint64_t>(rotate_seed);
    }
    const Similarity t = NormalizeForCommand(&m, no, path);
    if (applied) *applied = t;
  } else {
    CheckCoordinateRange(m, path);
  }
  return m;
}

int CmdSdf(const Args& args) {
  if (args.positional.size() != 2) Usage("sdf needs MESH and OUT");
  ThreadLimit limit(args.Has("--threads") ? ParseInt(args.Get("--threads"), "--threads", 0, 4096) : 0);
  if (args.Has("--curve")) {
    // 2D: a polyline file (.obj with 'l' lines, .txt, .poly) or a built-in curve name.
    const std::string& in = args.positional[0];
    const auto names = BuiltinCurveNames();
    Polyline curve = std::find(names.begin(), names.end(), in) != names.end() ? MakeBuiltinCurve(in) : ReadPolyline(in);
    if (!args.Has("--no-normalize")) NormalizeCurve(&curve, 1.0, true);
    Context ctx(1);
    SdfSamples s2;
    if (args.Has("--random")) {
      s2 = SampleSdfRandom2D(curve, ParseInt64(args.Get("--random"), "--random", 1, 1000000000), -1.0, 1.0, ctx);
    } else {
      SdfGrid2DOptions o;
      o.n = args.Has("--n") ? ParseInt(args.Get("--n"), "--n", 1, SdfGrid2DOptions::kMaxN) : 20;
      s2 = SampleSdfGrid2D(curve, o, ctx);
    }
    const std::string out = args.positional[1];
    WriteSdf(out, s2);  // by extension: .npy, .npz, text
    std::fprintf(stderr, "wrote %lld 2D SDF samples to %s\n", static_cast<long long>(s2.Size()), out.c_str());
    return 0;
  }
  Similarity to_frame;
  const Mesh m = LoadMeshNormalized(args.positional[0], !args.Has("--no-normalize"),
                                    args.Has("--rotate") ? ParseInt(args.Get("--rotate"), "--rotate", 0, INT_MAX) : -1, &to_frame);
  Context ctx(1);
  ctx.set_log([](LogLevel l, const std::string& msg) {
    if (l >= LogLevel::kWarning) std::fprintf(stderr, "arcs: warning: %s\n", msg.c_str());
  });
  SdfSamples s;
  SdfSignReport sign;
  if (args.Has("--random")) {
    s = SampleSdfRandom(m, ParseInt64(args.Get("--random"), "--random", 1, 1000000000), -1.0, 1.0, ctx,
                        SdfSign::kFastWindingNumber, SdfInside::kVoxelizer, &sign);
  } else {
    SdfGridOptions o;
    o.n = args.Has("--n") ? ParseInt(args.Get("--n"), "--n", 1, SdfGridOptions::kMaxN) : 20;
    s = SampleSdfGrid(m, o, ctx, &sign);
  }
  std::fprintf(stderr, "sign: %s rule, %lld unbalanced edges, %lld of %lld samples inside (%lld by the open-mesh shell)\n",
               sign.rule.c_str(), static_cast<long long>(sign.unbalanced_edges), static_cast<long long>(sign.inside),
               static_cast<long long>(s.Size()), static_cast<long long>(sign.shell_samples));
  const std::string out = args.positional[1];
  WriteSdf(out, s);  // by extension: .npy (grid or (N, 4)), .npz (U, S, bounds), text
  if (!args.Has("--no-normalize"))
    WriteTransformSidecar(out, to_frame, "SDF samples of " + fs::path(args.positional[0]).filename().string() +
                                             " in its normalised frame (arcs sdf)");
  std::fprintf(stderr, "wrote %lld SDF samples to %s\n", static_cast<long long>(s.Size()), out.c_str());
  return 0;
}

int CmdReconstruct(Registry& registry, const Args& args, int argc, char** argv) {
  if (args.positional.size() != 2) Usage("reconstruct needs SDF (input samples) and OUT (mesh file)");
  if (IsPointReconstruction(registry, args.positional[0], args.Get("--method")))
    return CmdReconstructPoints(registry, argc, argv);
  const std::string method = args.Get("--method", "rfta");
  const StageInfo& info = registry.Get(method);
  if (info.role != Role::kSdfToMesh)
    Usage("--method " + method + " is a " + RoleName(info.role) + " stage; an sdf_to_mesh stage is needed");
  const ParamMap given = DecodeGivenParams(registry, method, args.All("--param"), "--param");
  const ParamMap params = registry.Resolve(method, given);
  {  // formats by extension, before any work
    const std::string e = fs::path(args.positional[1]).extension().string();
    const bool curve_ext = e == ".txt" || e == ".svg" || e == ".poly" || e == ".obj";
    if (!curve_ext && SupportedMeshExtensions().find(e.empty() ? "?" : e) == std::string::npos)
      throw InputError(args.positional[1], 0, "unsupported output extension '" + e + "' (meshes: " +
                                                  SupportedMeshExtensions() + "; 2D curves: .obj .txt .poly .svg)");
  }
  CaseData data;
  data.registry = &registry;
  data.samples = ReadSdf(args.positional[0]);
  Context ctx(args.Has("--seed") ? static_cast<std::uint64_t>(ParseInt64(args.Get("--seed"), "--seed", 0)) : 1);
  ctx.set_log([](LogLevel l, const std::string& m) {
    if (l >= LogLevel::kWarning) std::fprintf(stderr, "%s\n", m.c_str());
  });
  ThreadLimit limit(args.Has("--threads") ? ParseInt(args.Get("--threads"), "--threads", 0, 4096) : 0);
  const auto t0 = std::chrono::steady_clock::now();
  registry.Get(method).factory(params)->Run(ctx, data);
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (data.samples->dim == 2) {
    if (!data.output_curve || data.output_curve->Empty()) throw Error(method + " produced an empty curve");
    WritePolyline(args.positional[1], *data.output_curve);  // .obj/.txt/.poly ('v x y 0', 'l i j ...') or .svg
    if (args.Has("--points")) {
      if (!data.points) throw Error(method + " produced no oriented points to write to " + args.Get("--points"));
      WritePointCloud(args.Get("--points"), *data.points);
    }
    const CurveTopology t = ComputeCurveTopology(*data.output_curve);
    std::fprintf(stderr, "%s: %lld samples -> %d vertices, %d edges (%d components, %d open ends) in %.2f s -> %s\n",
                 method.c_str(), static_cast<long long>(data.samples->Size()), data.output_curve->NumVertices(),
                 data.output_curve->NumEdges(), t.components, t.open_ends, secs, args.positional[1].c_str());
    return 0;
  }
  if (!data.output || data.output->Empty()) throw Error(method + " produced an empty mesh");
  // Samples with a transform sidecar (from `arcs sdf`) are in a normalised
  // frame: the mesh goes back to the input mesh's frame unless --frame normalized.
  Similarity to_frame;
  const bool framed = ReadTransformSidecar(args.positional[0], &to_frame);
  const std::string frame = args.Get("--frame", "input");
  if (frame != "input" && frame != "normalized") Usage("--frame must be input or normalized, got '" + frame + "'");
  if (framed && frame == "input") {
    *data.output = ApplyInverseSimilarity(to_frame, *data.output);
    if (data.points) ApplySimilarity(to_frame.Inverse(), &data.points->P);
  }
  WriteMesh(args.positional[1], *data.output);
  if (framed && frame == "normalized")
    WriteTransformSidecar(args.positional[1], to_frame, "mesh in the normalised frame of " + args.positional[0]);
  if (args.Has("--points")) {
    if (!data.points) throw Error(method + " produced no oriented points to write to " + args.Get("--points"));
    WritePointCloud(args.Get("--points"), *data.points);
  }
  const Topology t = ComputeTopology(*data.output);
  std::fprintf(stderr, "%s: %lld samples -> %d vertices, %d faces (closed %d, genus %d) in %.2f s -> %s\n",
               method.c_str(), static_cast<long long>(data.samples->Size()), t.vertices, t.faces, t.closed, t.genus,
               secs, args.positional[1].c_str());
  return 0;
}

int CmdShape(const Args& args) {
  if (args.positional.size() == 1 && args.positional[0] == "list") {
    std::printf("3D: sphere torus knot two_tori\n2D:");
    for (const auto& c : BuiltinCurveNames()) std::printf(" %s", c.c_str());
    std::printf("\n");
    return 0;
  }
  if (args.positional.size() != 2) Usage("shape needs NAME and OUT");
  const auto curves = BuiltinCurveNames();
  if (std::find(curves.begin(), curves.end(), args.positional[0]) != curves.end()) {
    WritePolyline(args.positional[1], MakeBuiltinCurve(args.positional[0]));
    return 0;
  }
  WriteMesh(args.positional[1], MakeBuiltinShape(args.positional[0]));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  // libgomp (used by PCL's Poisson) spin-waits by default, which on a busy
  // 2-core machine costs ~3x the CPU time; it reads OMP_WAIT_POLICY once at
  // load time, so set it and re-execute ourselves when it is absent.
  if (!std::getenv("OMP_WAIT_POLICY") && !std::getenv("ARCS_NO_REEXEC")) {
    setenv("OMP_WAIT_POLICY", "PASSIVE", 1);
    setenv("ARCS_NO_REEXEC", "1", 1);
    execv("/proc/self/exe", argv);  // returns only on failure: carry on as we are
  }
  KeepFreedMemory();  // freed memory reused, not faulted in again per solve (orchestration/memory.h)
  const GlobalOptions global = ExtractGlobalOptions(&argc, argv);  // --plugin, --threads anywhere
  if (global.version) {
    std::printf("arcs 0.1.0 (git %s, %s build, plugin API %d)\n", GitRevision(), BuildType(), ARCS_PLUGIN_API_VERSION);
    return 0;
  }
  if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h") || !std::strcmp(argv[1], "help")) {
    std::printf("%s", kUsage);
    return argc < 2 ? 2 : 0;
  }
  const std::string cmd = argv[1];
  try {
    Registry registry;
    RegisterBuiltinStages(registry);
    for (const auto& p : global.plugins) LoadPlugin(registry, p);
    if (global.help && PrintCommandHelp(registry, cmd, argc, argv)) return 0;
    // --threads: a process-wide limit, and passed on to the commands that take it.
    std::unique_ptr<ThreadLimit> thread_limit;
    std::vector<char*> with_threads(argv, argv + argc);
    std::string threads_text = std::to_string(global.threads);
    if (global.has_threads) {
      thread_limit = std::make_unique<ThreadLimit>(global.threads);
      if (cmd == "run" || cmd == "reconstruct" || cmd == "voxelize" || cmd == "morph") {
        static std::string flag = "--threads";
        with_threads.push_back(flag.data());
        with_threads.push_back(threads_text.data());
        with_threads.push_back(nullptr);
        argv = with_threads.data();
        argc += 2;
      }
    }
    if (cmd == "list" || cmd == "describe") {
      const Args a = Parse(argc, argv, 2, {"--plugin"}, {});
      LoadPlugins(registry, a);
      if (cmd == "list") return CmdList(registry);
      if (a.positional.size() != 1) Usage("describe needs one stage name");
      return CmdDescribe(registry, a.positional[0]);
    }
    if (cmd == "run") {
      const Args a = Parse(argc, argv, 2, {"--plugin", "--set", "--jobs", "--threads", "--out", "--shard"},
                           {"--retry-failed", "--no-isolate", "--quiet", "--save-outputs", "--dry-run"});
      LoadPlugins(registry, a);
      return CmdRun(registry, a, argc, argv);
    }
    if (cmd == "table") return CmdTable(Parse(argc, argv, 2, {"--tables", "--out"}, {}));
    if (cmd == "sdf")
      return CmdSdf(Parse(argc, argv, 2, {"--n", "--random", "--rotate", "--threads"}, {"--no-normalize", "--curve"}));
    if (cmd == "eval") return CmdEval(argc, argv);
    if (cmd == "reconstruct") {
      const Args a = Parse(argc, argv, 2,
                           {"--plugin", "--method", "--param", "--seed", "--threads", "--points", "--frame",
                            "--normals-param"},
                           {"--estimate-normals"});
      LoadPlugins(registry, a);
      return CmdReconstruct(registry, a, argc, argv);
    }
    if (cmd == "shape") return CmdShape(Parse(argc, argv, 2, {}, {}));
    if (cmd == "voxelize") return CmdVoxelize(registry, argc, argv);
    if (cmd == "morph") return CmdMorph(registry, argc, argv);
    if (cmd == "slurm") return CmdSlurm(registry, argc, argv);
    if (cmd == "plot" || cmd == "render" || cmd == "report") return CmdPlot(argc, argv);
    if (cmd == "version") {
      std::printf("arcs 0.1.0 (git %s, %s build, plugin API %d)\n", GitRevision(), BuildType(), ARCS_PLUGIN_API_VERSION);
      return 0;
    }
    Usage("unknown command '" + cmd + "'");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "arcs: error: %s\n", e.what());
    return 1;
  }
}
