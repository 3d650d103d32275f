// Executing one case: load and normalise the item, run the input pipeline,
// the method (timed, with its peak memory), then the metrics.
#include "orchestration/case_exec.h"

#include "orchestration/memory.h"
#include "framework/geometry/builtin_shapes.h"
#include "framework/geometry/normalize.h"
#include "framework/geometry/transform_file.h"
#include "framework/io/mesh_io.h"
#include "framework/io/points_io.h"
#include "framework/geometry/curves.h"
#include "framework/spatial/topology.h"
#include "framework/util/parallel.h"
#include "framework/util/rng.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>

namespace arcs {

namespace {

double Seconds(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

std::string Num(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

// Stage::Run checks each stage's contract and prefixes its errors with the
// stage's name once (no second prefix here: that gave "x: x: ...").
void RunStages(const std::vector<StageSpec>& stages, const Registry& registry, Context& ctx, CaseData& data) {
  for (const auto& s : stages) registry.Create(s)->Run(ctx, data);
}

// Letters, digits and "._=-" stay; anything else becomes '_'.
std::string FileSafe(const std::string& s) {
  std::string out;
  for (char ch : s) {
    const bool keep = std::isalnum(static_cast<unsigned char>(ch)) || ch == '.' || ch == '_' || ch == '=' || ch == '-';
    out += keep ? ch : '_';
  }
  return out;
}

// Writes through a temporary name, so an interrupted run leaves no partial file.
template <class WriteFn>
std::string WriteAtomically(const std::string& path, WriteFn write) {
  namespace fs = std::filesystem;
  const std::string part = path + ".part" + fs::path(path).extension().string();
  write(part);
  fs::rename(part, path);
  return fs::path(path).filename().string();
}

// Loads the case's item into `data` (reference mesh or curve, or points and
// their optional reference) and normalises it; returns the transform from
// the dataset file's frame to the case's normalised frame.
Similarity LoadItem(const Case& c, Context& ctx, CaseData* data,
                    const std::function<void(const std::string&, const std::string&)>& set) {
  const DatasetItem& item = c.source;
  Similarity to_case_frame;
  NormalizeOptions no;
  no.center = c.normalize.center;
  no.longest_side = c.normalize.longest_side;
  no.random_rotation = c.normalize.random_rotation;
  no.rotation_seed = static_cast<std::uint64_t>(c.normalize.rotation_seed);
  switch (item.kind) {
    case ItemKind::kBuiltinCurve:
    case ItemKind::kCurveFile:
      data->reference_curve =
          item.kind == ItemKind::kBuiltinCurve ? MakeBuiltinCurve(item.name) : ReadPolyline(item.path);
      if (c.normalize.enabled) NormalizeCurve(&*data->reference_curve, c.normalize.longest_side, c.normalize.center);
      set("ref_components", std::to_string(ComputeCurveTopology(*data->reference_curve).components));
      return to_case_frame;
    case ItemKind::kPointFile: {
      PointReadReport report;
      data->points = ReadPointCloud(item.path, &report);
      if (!report.skipped_lines.empty())
        ctx.Warn(item.path + ": skipped " + std::to_string(report.skipped_lines.size()) +
                 " malformed line(s), first at line " + std::to_string(report.skipped_lines.front()));
      for (const auto& w : report.warnings) ctx.Warn(item.path + ": " + w);
      set("input_points", std::to_string(data->points->Size()));
      if (!c.reference_path.empty()) data->reference = ReadMesh(c.reference_path);
      if (c.normalize.enabled) {
        const Similarity t = NormalizeTransform(data->points->P, no);
        to_case_frame = t;
        ApplySimilarity(t, &data->points->P);
        if (data->points->HasNormals()) {
          // Rotation only: normals are directions.
          data->points->N = (data->points->N * t.rotation.transpose()).eval();
        }
        if (data->reference) *data->reference = ApplySimilarity(t, *data->reference);
      }
      return to_case_frame;
    }
    case ItemKind::kBuiltinShape:
    case ItemKind::kMeshFile:
      if (item.kind == ItemKind::kBuiltinShape) {
        data->reference = MakeBuiltinShape(item.name);
      } else {
        MeshReadReport mrep;
        data->reference = ReadMesh(item.path, &mrep);
        for (const auto& w : mrep.warnings) ctx.Warn(item.path + ": " + w);
        if (data->reference->NumFaces() == 0)
          throw InputError(item.path, 0, "the mesh has no triangle faces (" +
                                             std::to_string(data->reference->NumVertices()) + " vertices)");
      }
      if (c.normalize.enabled) {
        try {
          to_case_frame = Normalize(&*data->reference, no);
        } catch (const InputError&) {
          throw;
        } catch (const Error& e) {
          throw InputError(item.Key(), 0, e.what());
        }
      }
      return to_case_frame;
  }
  return to_case_frame;
}

}  // namespace

std::string OutputStem(const Case& c) {
  // The case's label ("bunny n=20 | grid | MC") with " | " as "__", made file-safe.
  std::string s = c.Label();
  for (size_t pos; (pos = s.find(" | ")) != std::string::npos;) s.replace(pos, 3, "__");
  s = FileSafe(s);
  // File names are limited to 255 bytes (NAME_MAX) and several varying
  // nested parameters make labels longer ("File name too long"): a long label
  // keeps its first kMaxLabel characters and a hash of the whole label; the
  // case id that follows keeps the name unique.
  constexpr std::size_t kMaxLabel = 120;
  if (s.size() > kMaxLabel) {
    char hash[20];
    std::snprintf(hash, sizeof hash, "%08llx",
                  static_cast<unsigned long long>(Fnv1a64(s) & 0xffffffffull));
    s = s.substr(0, kMaxLabel) + "~" + hash;
  }
  return s + "__" + c.id;
}

Row ExecuteCase(const Case& c, const Registry& registry, int threads, const Context::LogFn& log,
                const std::string& outputs_dir) {
  const auto t0 = std::chrono::steady_clock::now();
  ThreadLimit limit(threads);
  Row row;
  row.emplace_back("case_id", c.id);
  row.emplace_back("status", "ok");
  row.emplace_back("error", "");
  row.emplace_back("dataset", c.dataset);
  row.emplace_back("item", c.item);
  row.emplace_back("input", c.input);
  row.emplace_back("method", c.method);
  row.emplace_back("seed", std::to_string(c.seed));
  for (const auto& p : c.params) row.push_back(p);
  auto set = [&](const std::string& k, const std::string& v) {
    for (auto& [key, val] : row)
      if (key == k) {
        val = v;
        return;
      }
    row.emplace_back(k, v);
  };

  std::int64_t peak_before_method = 0;  // the method's peak is measured after a reset
  CaseData data;
  data.registry = &registry;
  data.item = c.item;
  data.item_path = c.source.Key();
  // Seeds: inputs and metrics depend only on (seed, item, input), so every
  // method of a case group sees the same samples and the same metric draws;
  // the method's own stream also depends on the method (or, with
  // `method_seed: shared`, is the same for every method).
  const std::string item_key = c.source.Key() + "|" + c.input;
  std::string input_key = item_key;
  for (const auto& s : c.input_stages) input_key += "|" + s.stage + FormatParamValue(std::make_shared<StageSpec>(s));
  Context ctx(HashSeed(c.seed, Fnv1a64(input_key)));
  ctx.set_log(log);
  try {
    // 1. The dataset item.
    const Similarity to_case_frame = LoadItem(c, ctx, &data, set);  // dataset file -> the case's frame
    if (data.reference) {
      const Topology rt = ComputeTopology(*data.reference);
      set("ref_faces", std::to_string(rt.faces));
      set("ref_genus", std::to_string(rt.genus));
      set("ref_closed", rt.closed ? "1" : "0");
    }

    // 2. Input generation.
    const auto t1 = std::chrono::steady_clock::now();
    RunStages(c.input_stages, registry, ctx, data);
    const auto t2 = std::chrono::steady_clock::now();
    set("input_wall_s", Num(Seconds(t1, t2)));
    if (data.samples) set("input_samples", std::to_string(data.samples->Size()));

    // 3. The method, timed, with its own peak memory.
    Context mctx(HashSeed(ctx.seed(), Fnv1a64(c.MethodSeedKey())));
    mctx.set_log(log);
    peak_before_method = PeakRssBytes();
    const bool reset = ResetPeakRss();
    const std::int64_t rss_before = CurrentRssBytes();
    const auto t3 = std::chrono::steady_clock::now();
    RunStages(c.method_stages, registry, mctx, data);
    const auto t4 = std::chrono::steady_clock::now();
    set("method_wall_s", Num(Seconds(t3, t4)));
    if (reset) {
      set("method_peak_rss_mb", Num(PeakRssBytes() / 1048576.0));
      set("method_extra_rss_mb", Num((PeakRssBytes() - rss_before) / 1048576.0));
    }
    for (const auto& [k, v] : data.metrics) set(k, Num(v));
    data.metrics.clear();
    if (!outputs_dir.empty()) {
      const std::string base = (std::filesystem::path(outputs_dir) / OutputStem(c)).string();
      if (data.output && !data.output->Empty()) {
        set("output_file", WriteAtomically(base + ".ply", [&](const std::string& f) { WriteMesh(f, *data.output); }));
        WriteTransformSidecar(base + ".ply", to_case_frame, "the case's normalised frame of " + c.source.Key());
      }
      else if (data.output_curve && !data.output_curve->Empty())
        set("output_file",
            WriteAtomically(base + ".obj", [&](const std::string& f) { WritePolyline(f, *data.output_curve); }));
      if (data.reference && !data.reference->Empty()) {  // once per item, in the outputs' frame (renders)
        // Cases of one item may run at once: each writes its own temporary, then renames.
        const auto ref = std::filesystem::path(outputs_dir) / (FileSafe(c.dataset + "_" + c.item) + "__reference.ply");
        const std::string part = ref.string() + "." + c.id + ".part.ply";
        WriteMesh(part, *data.reference);
        std::filesystem::rename(part, ref);
        set("reference_file", ref.filename().string());
      }
      if (c.source.kind != ItemKind::kPointFile && data.points && data.points->Size() > 0)
        set("output_points_file", WriteAtomically(base + "_points.ply", [&](const std::string& f) {
              WritePointCloud(f, *data.points);
            }));
    }

    // 4. Metrics (same stream for every method).
    Context ectx(HashSeed(ctx.seed(), Fnv1a64("metrics")));
    ectx.set_log(log);
    RunStages(c.metric_stages, registry, ectx, data);
    for (const auto& [k, v] : data.metrics) set(k, Num(v));
  } catch (const std::exception& e) {
    set("status", "failed");
    set("error", e.what());
    for (const auto& [k, v] : data.metrics) set(k, Num(v));
  }
  set("wall_s", Num(Seconds(t0, std::chrono::steady_clock::now())));
  set("peak_rss_mb", Num(std::max(peak_before_method, PeakRssBytes()) / 1048576.0));
  return row;
}

}  // namespace arcs
