// arcs eval MESH REFERENCE: the paper's metrics with both meshes in one frame.
//
// --frame reference (default): the transform that normalises REFERENCE
// (bounding box centred, longest side 1: the paper's evaluation frame) is
// applied to MESH too, so a mesh evaluated against itself scores the
// sampling floor, and an output written in the input's frame is compared
// where it lies. --frame each normalises each mesh by its own box (shape
// only, ignoring placement and scale); --frame none compares them as stored.
// (Before issue 14 only REFERENCE was normalised, silently: the issue
// measured Chamfer 0.41 for a mesh against itself.)
#include "app/cli.h"
#include "app/commands.h"
#include "framework/error.h"
#include "framework/eval/metrics.h"
#include "framework/geometry/builtin_shapes.h"
#include "framework/geometry/normalize.h"
#include "framework/geometry/transform_file.h"
#include "framework/io/mesh_io.h"
#include "framework/io/sdf_io.h"
#include "app/mesh_input.h"
#include "framework/spatial/topology.h"

#include <cstdio>
#include <string>
#include <utility>
#include <vector>

namespace arcs {
namespace {

Mesh LoadMeshOrShape(const std::string& path) {
  return path.rfind("shape:", 0) == 0 ? MakeBuiltinShape(path.substr(6)) : cli::ReadMeshForCommand(path);
}

std::string JsonNum(double x) {
  if (!std::isfinite(x)) return "null";
  char b[40];
  std::snprintf(b, sizeof b, "%.9g", x);
  return b;
}

std::string JsonStr(const std::string& s) {
  std::string o = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') o += '\\';
    if (static_cast<unsigned char>(c) < 0x20) {
      char b[8];
      std::snprintf(b, sizeof b, "\\u%04x", c);
      o += b;
      continue;
    }
    o += c;
  }
  return o + "\"";
}

}  // namespace

int CmdEval(int argc, char** argv) {
  const cli::Args a = cli::Parse(argc, argv, 2, {"--samples", "--sdf", "--frame"}, {"--no-normalize", "--json"});
  if (a.positional.size() != 2) cli::Usage("eval needs MESH and REFERENCE");
  std::string frame = a.Get("--frame", a.Has("--no-normalize") ? "none" : "reference");
  if (a.Has("--no-normalize") && frame != "none") cli::Usage("--no-normalize and --frame " + frame + " exclude each other");
  if (frame != "reference" && frame != "each" && frame != "none")
    cli::Usage("--frame must be reference, each or none, got '" + frame + "'");
  const std::int64_t n = a.Has("--samples") ? cli::ParseInt64(a.Get("--samples"), "--samples", 1, 1000000000) : 1000000;
  if (n < 1) cli::Usage("--samples must be >= 1");
  Mesh ref = LoadMeshOrShape(a.positional[1]);
  Mesh m = LoadMeshOrShape(a.positional[0]);
  if (ref.Empty()) throw InputError(a.positional[1], 0, "the reference mesh has no faces");
  if (m.Empty()) throw InputError(a.positional[0], 0, "the mesh has no faces");
  Similarity ref_t;
  // A normalisation that overflows or underflows names the file it came from.
  auto transform_of = [](const Mesh& mesh, const std::string& path) {
    try {
      return NormalizeTransform(mesh.V, NormalizeOptions{});
    } catch (const InputError&) {
      throw;
    } catch (const Error& e) {
      throw InputError(path, 0, e.what());
    }
  };
  if (frame != "none") {
    ref_t = transform_of(ref, a.positional[1]);
    ref = ApplySimilarity(ref_t, ref);
    m = ApplySimilarity(frame == "reference" ? ref_t : transform_of(m, a.positional[0]), m);
  } else {
    cli::CheckCoordinateRange(ref, a.positional[1]);
    cli::CheckCoordinateRange(m, a.positional[0]);
  }
  std::vector<std::pair<std::string, double>> metrics = {
      {"chamfer", ChamferPaper(m, ref, n, 1)},
      {"hausdorff", HausdorffPaper(m, ref)},
      {"chamfer_p2s", ChamferPointToSurface(m, ref, n, 1)},
      {"hausdorff_sampled", HausdorffSampled(m, ref, n, 1)},
  };
  if (a.Has("--sdf")) {
    // Samples as `arcs sdf` writes them: in the normalised frame named by
    // their .transform.json sidecar (mapped back to the reference's stored
    // frame first), or, without one, in the reference's stored frame.
    SdfSamples s = ReadSdf(a.Get("--sdf"));
    Similarity st;
    if (ReadTransformSidecar(a.Get("--sdf"), &st)) ApplySimilarity(st.Inverse(), &s);
    if (frame != "none") ApplySimilarity(ref_t, &s);
    metrics.emplace_back("e_sdf", EnergySdf(s, m));
  }
  const Topology t = ComputeTopology(m);
  if (a.Has("--json")) {
    std::string j = "{\"mesh\": " + JsonStr(a.positional[0]) + ", \"reference\": " + JsonStr(a.positional[1]) +
                    ", \"frame\": " + JsonStr(frame) + ", \"samples\": " + std::to_string(n);
    for (const auto& [k, v] : metrics) j += ", " + JsonStr(k) + ": " + JsonNum(v);
    j += ", \"closed\": " + std::string(t.closed ? "true" : "false") + ", \"manifold\": " + (t.manifold ? "true" : "false") +
         ", \"genus\": " + std::to_string(t.genus) + ", \"components\": " + std::to_string(t.components) +
         ", \"vertices\": " + std::to_string(t.vertices) + ", \"faces\": " + std::to_string(t.faces) + "}\n";
    std::fputs(j.c_str(), stdout);
    return 0;
  }
  std::printf("frame              %s\n", frame.c_str());
  for (const auto& [k, v] : metrics) std::printf("%-18s %.6g\n", k.c_str(), v);
  std::printf("closed %d  manifold %d  genus %d  components %d  vertices %d  faces %d\n", t.closed, t.manifold,
              t.genus, t.components, t.vertices, t.faces);
  return 0;
}

}  // namespace arcs
