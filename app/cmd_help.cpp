// `arcs C --help` for every subcommand, and the global options that may
// appear anywhere on the command line (--plugin FILE, --threads T).
//
// The option lists of commands that run a stage are generated from the
// stage's schema (the one `arcs describe` prints), so they cannot drift.
#include "app/cli.h"
#include "app/commands.h"
#include "registry/plugin.h"

#include <cstdio>
#include <cstring>
#include <map>
#include <string>

namespace arcs {
namespace {

struct CommandHelp {
  const char* usage;    // first line(s)
  const char* details;  // options and notes
};

// Commands with a help text of their own (voxelize, morph: generated from
// their stages' schemas) are not listed here:
// their own --help is printed.
const std::map<std::string, CommandHelp>& HelpTable() {
  static const std::map<std::string, CommandHelp> t = {
      {"run", {"arcs run EXP.yaml [options]",
               "Expands the experiment into cases and runs each (in a worker process); resumes\n"
               "finished cases by their id. Results: DIR/results.csv, tables/, config.resolved.yaml,\n"
               "provenance.yaml.\n\n"
               "  --set path.to.param=value   override any YAML value before validation (repeatable),\n"
               "                              e.g. --set inputs.grid.sdf_grid.n=[20,40] --set seed=3\n"
               "  --jobs N                    cases at once (default 1)\n"
               "  --threads T                 threads per case (default cores / jobs)\n"
               "  --out DIR                   results directory (default results/<name>)\n"
               "  --retry-failed              re-run cases recorded as failed\n"
               "  --no-isolate                run cases in this process (no worker processes)\n"
               "  --quiet                     no progress line, no tables on stdout\n"
               "  --save-outputs              each case's mesh/curve/points into DIR/outputs/\n"}},
      {"table", {"arcs table RESULTS_DIR [--tables EXP.yaml]\n"
                 "       arcs table RESULTS... --tables EXP.yaml --out DIR",
                 "Rebuilds the tables (.md .csv .tex) from RESULTS_DIR/results.csv without re-running.\n"
                 "With several RESULTS (results directories or results .csv files: a table run in parts,\n"
                 "e.g. docs/runs/), one table of their union (rows keyed by case id) into DIR/tables/.\n\n"
                 "  --tables EXP.yaml   take the `tables:` from this file (default RESULTS_DIR/config.resolved.yaml)\n"
                 "  --out DIR           where the merged tables go (required with several RESULTS)\n"}},
      {"list", {"arcs list", "Every registered stage (built-in and plugins), by role.\n"}},
      {"describe", {"arcs describe STAGE",
                    "A stage's parameters: type, default (the paper's), allowed range and doc line.\n"
                    "The same schema drives YAML decoding, --set, `arcs reconstruct --param` and the\n"
                    "Python module's keyword arguments.\n"}},
      {"sdf", {"arcs sdf MESH OUT [options]",
               "Samples the signed distance of MESH (a mesh file or shape:NAME) with the paper's protocol.\n"
               "OUT by extension: .npy (a grid (nx, ny, nz) + OUT.npy.bounds; --random: an (N, 4) array\n"
               "of rows x y z s), .npz (U, S and for a grid bounds, as numpy.savez), .txt/.xyzs/.sdf\n"
               "(text lines 'x y z s'). The mesh is normalised (bounding box centred, longest side 1) unless\n"
               "--no-normalize; the transform is written beside OUT as OUT.transform.json.\n\n"
               "  --n N            grid cells per axis: (N+1)^3 nodes of linspace(-1, 1, N+1) (default 20)\n"
               "  --random COUNT   COUNT uniform samples in [-1, 1]^3 instead of a grid\n"
               "  --no-normalize   keep the mesh's coordinates\n"
               "  --rotate SEED    a random rotation after normalising (the paper's many-shapes protocol)\n"
               "  --curve          MESH is a 2D polyline file or a built-in curve (`arcs shape list`)\n"}},
      {"eval", {"arcs eval MESH REFERENCE [options]",
                "The paper's metrics of MESH against REFERENCE, both in one frame.\n\n"
                "  --frame F        reference (default): both meshes moved by the transform that normalises\n"
                "                   REFERENCE (bounding box centred, longest side 1), the paper's frame;\n"
                "                   each: each mesh normalised by its own box; none: as stored\n"
                "  --no-normalize   the same as --frame none\n"
                "  --samples N      area-uniform samples per mesh (default 1 000 000)\n"
                "  --sdf FILE       SDF samples (in REFERENCE's stored frame) for e_sdf\n"
                "  --json           one JSON object on stdout instead of the text table\n"}},
      {"shape", {"arcs shape NAME OUT | arcs shape list",
                 "Writes a built-in shape (sphere, torus, knot, two_tori) as a mesh file, or a built-in 2D\n"
                 "curve as a polyline (.obj/.txt/.svg).\n"}},
      {"version", {"arcs version | arcs --version", "Version, git revision, build type and plugin API version.\n"}},
  };
  return t;
}

const char* kGlobalHelp =
    "\nglobal options (anywhere on the line):\n"
    "  --plugin FILE    load a plugin (also $ARCS_PLUGIN_PATH, or `plugins:` in YAML)\n"
    "  --threads T      worker threads (default: all cores)\n"
    "  --help, -h       this help\n";

void PrintStageOptions(const StageInfo& s) {
  std::printf("\n%s (%s): %s\n", s.name.c_str(), RoleName(s.role), s.doc.c_str());
  if (s.params.specs().empty()) {
    std::printf("  no parameters\n");
    return;
  }
  for (const auto& p : s.params.specs())
    std::printf("  --param %-24s %-7s default %-14s %-20s %s\n", (p.name + "=V").c_str(), ParamTypeName(p.type),
                FormatParamValue(p.default_value).c_str(), p.RangeText().c_str(), p.doc.c_str());
}

void PrintReconstructHelp(const Registry& registry, const std::string& method) {
  std::printf(
      "usage: arcs reconstruct INPUT OUT [--method STAGE] [--param name=value]... [options]\n\n"
      "A mesh OUT (.ply .obj .off .stl; a 2D curve: .obj .txt .svg) from\n"
      "  SDF samples  INPUT .npy (grid, or (N, 4) rows x y z s), .npz (U, S, bounds), .txt/.xyzs/.sdf,\n"
      "               with an sdf_to_mesh method (default rfta), or\n"
      "  points       INPUT .ply .xyz .pwn .pcd (ascii, binary, binary_compressed) or .npy (N, 3) / (N, 6)\n"
      "               (x y z [nx ny nz]), with a reconstructor (default screened_poisson when INPUT is a\n"
      "               point cloud file). Normals are estimated (estimate_normals) when the method needs\n"
      "               them and the cloud has none, or always with --estimate-normals. The points are\n"
      "               moved into the unit frame (bounding box centred, longest side 1) for the method\n"
      "               and the mesh is written back in INPUT's frame (--frame normalized: in the unit\n"
      "               frame, with the transform in OUT.transform.json).\n\n"
      "  --method STAGE           any sdf_to_mesh or reconstructor stage (below)\n"
      "  --param name=value       a parameter of that stage (repeatable; `--method X --help` lists them);\n"
      "                           a stage-valued one as its default is printed, STAGE(name=value, ...),\n"
      "                           starting from the default's parameters when STAGE is the default's:\n"
      "                           --param 'reconstructor=screened_poisson(point_weight=15)'\n"
      "  --normals-param n=v      a parameter of estimate_normals (repeatable)\n"
      "  --estimate-normals       estimate normals even when the cloud has some\n"
      "  --frame input|normalized the frame OUT is written in (points; default input)\n"
      "  --points PTS.ply         also write the method's oriented points (RFTA's tangency points)\n"
      "  --seed N                 random seed (default 1)\n");
  std::printf("\nsdf_to_mesh methods:");
  for (const StageInfo* s : registry.List())
    if (s->role == Role::kSdfToMesh) std::printf(" %s", s->name.c_str());
  std::printf("\nreconstructors:");
  for (const StageInfo* s : registry.List())
    if (s->role == Role::kReconstructor) std::printf(" %s", s->name.c_str());
  std::printf("\n");
  PrintStageOptions(registry.Get(method.empty() ? "rfta" : method));
  if (method.empty()) PrintStageOptions(registry.Get("screened_poisson"));
}

}  // namespace

GlobalOptions ExtractGlobalOptions(int* argc, char** argv) {
  GlobalOptions g;
  int out = 1;
  bool seen_command = false;
  for (int i = 1; i < *argc; ++i) {
    const std::string s = argv[i];
    auto value = [&](const std::string& key) -> std::string {
      if (s.size() > key.size() && s.compare(0, key.size() + 1, key + "=") == 0) return s.substr(key.size() + 1);
      if (i + 1 >= *argc) cli::Usage("option " + key + " needs a value");
      return argv[++i];
    };
    if (s == "--plugin" || s.rfind("--plugin=", 0) == 0) {
      g.plugins.push_back(value("--plugin"));
    } else if (s == "--threads" || s.rfind("--threads=", 0) == 0) {
      g.threads = cli::ParseInt(value("--threads"), "--threads");
      if (g.threads < 0) cli::Usage("--threads must be >= 0 (0 = all cores), got " + std::to_string(g.threads));
      g.has_threads = true;
    } else if (s == "--version" && !seen_command) {
      g.version = true;
    } else if ((s == "--help" || s == "-h") && seen_command) {
      g.help = true;
      argv[out++] = argv[i];  // kept: commands with their own help (voxelize, morph) see it
    } else {
      if (s.rfind("-", 0) != 0) seen_command = true;
      argv[out++] = argv[i];
    }
  }
  *argc = out;
  argv[out] = nullptr;
  return g;
}

bool PrintCommandHelp(const Registry& registry, const std::string& cmd, int argc, char** argv) {
  if (cmd == "reconstruct") {
    std::string method;
    for (int i = 2; i + 1 < argc; ++i)
      if (!std::strcmp(argv[i], "--method")) method = argv[i + 1];
    PrintReconstructHelp(registry, method);
    std::printf("%s", kGlobalHelp);
    return true;
  }
  const auto& t = HelpTable();
  const auto it = t.find(cmd);
  if (it == t.end()) return false;
  std::printf("usage: %s\n\n%s", it->second.usage, it->second.details);
  if (cmd == "describe" || cmd == "list") {
    std::printf("\nstages:");
    for (const StageInfo* s : registry.List()) std::printf(" %s", s->name.c_str());
    std::printf("\n");
  }
  std::printf("%s", kGlobalHelp);
  return true;
}

}  // namespace arcs
