// An experiment file, loaded: the Experiment struct, YAML loading and strict
// validation. The schema is documented in README.md ("Experiment files").
// Every error names the file, line and field
// ("exp.yaml:12: methods[0].pipeline[1].params.n: ..."). Loading order:
// YAML parse and structure check (yaml_check.h) -> --set overrides
// (overrides.h) -> keys and values decoded (yaml_decode.h), dataset items
// made (items.h), stage names and parameters checked against the registry
// -> ValidatePipelines (the data flow of every pipeline) -> tables
// (table_spec.h). Case expansion is expand.h.
#pragma once

#include "orchestration/items.h"
#include "orchestration/paths.h"
#include "orchestration/table_spec.h"
#include "orchestration/yaml_decode.h"
#include "registry/registry.h"

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace arcs {

struct NormalizeSpec {
  bool enabled = true;          // scale + centre as the paper's protocol
  double longest_side = 1.0;    // longest bounding-box side after scaling
  bool center = true;           // bounding-box centre moved to the origin
  bool random_rotation = false; // the paper's random rotation (seeded)
  std::int64_t rotation_seed = 1;
};

struct DatasetSpec {
  std::string name;
  // kMesh: each item is a mesh (file or built-in shape), the case's
  // reference. kPoints: each file is a point cloud (PLY/XYZ/PWN/PCD), the
  // case's points; `reference` (optional) is a mesh loaded as the reference,
  // normalised with the points' transform. kCurves: 2D polylines (files or
  // built-in curves), the reference curve.
  DatasetKind kind = DatasetKind::kMesh;
  std::string reference;
  std::vector<DatasetItem> items;  // `files` (resolved, each glob sorted) then `shapes`
  NormalizeSpec normalize;
};

// One stage of a pipeline with, for each parameter, the list of values to
// sweep (a single value when not swept).
struct StageEntry {
  std::string stage;
  std::vector<std::pair<std::string, std::vector<ParamValue>>> values;
  std::string where;  // "file:line" for messages
};

struct PipelineSpec {
  std::string name;
  std::vector<StageEntry> stages;
};

struct Experiment {
  std::string file;       // path of the YAML file
  std::string name;
  std::string description;
  std::uint64_t seed = 1;
  // The methods' random streams: one per method (each hashes its name into
  // the seed), or one shared by every method of a case group (common random
  // numbers: methods that differ only in a parameter see the same draws, so
  // an ablation written as several methods measures the parameter alone, as
  // a sweep inside one method does).
  bool shared_method_seed = false;
  const char* MethodSeedName() const { return shared_method_seed ? "shared" : "per_method"; }
  double case_timeout_s = 0;  // 0 = no limit
  // Write each case's output (mesh, 2D curve, the method's oriented points)
  // into <results>/outputs/ (also `arcs run --save-outputs`).
  bool save_outputs = false;
  std::vector<std::string> plugins;
  std::vector<DatasetSpec> datasets;
  std::vector<PipelineSpec> inputs;
  std::vector<PipelineSpec> methods;
  std::vector<StageEntry> metrics;
  std::vector<TableSpec> tables;
  YAML::Node resolved;  // the document after overrides, with defaults filled in
};

// Loads, overrides, validates. Plugins named in the file are loaded into
// `registry` before stage names are checked. Throws ExperimentError.
Experiment LoadExperiment(const std::string& path, const std::vector<std::string>& overrides,
                          Registry& registry);

// The per-pipeline checks that need the whole experiment (stages decoded,
// datasets known): LoadExperiment calls it once, after decoding `inputs`,
// `methods` and `metrics` and before any case is expanded. Each input
// pipeline is followed by each method and the metrics, over the datasets'
// kinds. Throws ExperimentError naming the file and line of the offending
// stage (StageEntry::where): the stage contract's data-flow check
// (Registry::CheckPipeline) — a stage reading a slot that neither the
// dataset item nor an earlier stage fills, or working in the other dimension.
void ValidatePipelines(const Experiment& exp, const Registry& registry);

}  // namespace arcs
