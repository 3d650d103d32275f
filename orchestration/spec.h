// YAML experiment files: parsing, strict validation and expansion into cases.
//
// The schema is documented in README.md ("Experiment files"). Every error
// names the file, line and field ("exp.yaml:12: methods[0].pipeline[1].params.n: ...").
#pragma once

#include "registry/registry.h"

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace arcs {

// Validation error located in an experiment file.
class ExperimentError : public Error {
 public:
  using Error::Error;
};

struct NormalizeSpec {
  bool enabled = true;          // scale + centre as the paper's protocol
  double longest_side = 1.0;    // longest bounding-box side after scaling
  bool center = true;           // bounding-box centre moved to the origin
  bool random_rotation = false; // the paper's random rotation (seeded)
  std::int64_t rotation_seed = 1;
};

struct DatasetSpec {
  std::string name;
  // "mesh": each file is a mesh, loaded as the case's reference.
  // "points": each file is a point cloud (PLY/XYZ/PWN/PCD), loaded as the
  // case's points; `reference` (optional) is a mesh loaded as the reference,
  // normalised with the points' transform.
  std::string kind = "mesh";
  std::string reference;
  std::vector<std::string> files;    // resolved, sorted; or "shape:<name>" for built-in shapes
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

struct GroupSpec {
  std::string name;
  std::vector<std::string> where;  // conditions "column op value", all must hold
};

struct ReferenceColumn {
  std::string metric;  // our metric this column sits beside
  std::string column;  // column in the reference CSV
  std::string label;   // header shown in the table
};

struct ReferenceSpec {
  std::string file;                                 // resolved path ("" = none)
  std::vector<std::pair<std::string, std::string>> match;  // ref column -> "group" | "rows" | our column
  std::vector<std::string> where;                   // filters on reference rows
  std::vector<ReferenceColumn> columns;
};

struct TableSpec {
  std::string name;
  std::vector<std::string> metrics;
  std::string rows;                 // a results column (suffix match allowed)
  std::string columns = "method";   // a results column
  std::string aggregate = "mean";   // mean | median | min | max | std | count
  std::vector<GroupSpec> groups;    // default: one group "all"
  std::vector<ReferenceSpec> references;
  std::string format = "%.4g";      // printf format of cells
  // Order of the column keys (from the experiment: its methods' YAML order
  // when columns is "method"); keys not listed follow in first-appearance
  // order. Without it, text keys keep first-appearance order.
  std::vector<std::string> column_order;
  // Paired means (the RFTA paper's Table 2 convention): a (dataset, item,
  // input, row key) counts only where every column key has an ok row; adds
  // a "shapes" column with the number of such items per row.
  bool paired = false;
  // Also writes <name>_failures: one row per failed case (row key, item,
  // column key, error).
  bool failures = false;
};

struct Experiment {
  std::string file;       // path of the YAML file
  std::string name;
  std::string description;
  std::uint64_t seed = 1;
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

// A fully resolved unit of work.
struct Case {
  std::string id;        // 16 hex digits, hash of the resolved configuration
  std::string dataset;
  std::string item;      // file stem or shape name
  std::string item_path; // file, or "shape:<name>"
  NormalizeSpec normalize;
  std::string kind = "mesh";   // DatasetSpec::kind
  std::string reference_path;  // points datasets: the reference mesh, if any
  std::string input;     // input pipeline name
  std::vector<StageSpec> input_stages;
  std::string method;
  std::vector<StageSpec> method_stages;
  std::vector<StageSpec> metric_stages;
  std::uint64_t seed = 1;  // the experiment's seed
  // Resolved parameters as results columns ("stage.param" -> text), in order.
  std::vector<std::pair<std::string, std::string>> params;
  // Parameter columns that vary across the experiment's cases (for labels).
  std::vector<std::string> varying;
  // Short human label: "bunny n=20 | grid | MC".
  std::string Label() const;
};

// Applies one "--set path.to.key=value" override to a YAML document. Path
// elements index mappings by key and sequences by an element's `name` or
// `stage` (or a number); inside a stage entry, an unknown key is looked up in
// its `params`. The value is parsed as YAML ("[10, 20]" is a list).
void ApplyOverride(YAML::Node& doc, const std::string& assignment);

// Loads, overrides, validates. Plugins named in the file are loaded into
// `registry` before stage names are checked. Throws ExperimentError.
Experiment LoadExperiment(const std::string& path, const std::vector<std::string>& overrides,
                          Registry& registry);

// Parses a `tables:` list (paths relative to base_dir).
std::vector<TableSpec> ParseTables(const std::string& file, const YAML::Node& node, const std::string& base_dir);
// The tables of an experiment (or resolved config) file; other keys ignored.
std::vector<TableSpec> LoadTableSpecs(const std::string& path);

// Expands datasets x inputs x methods x the cartesian product of every
// swept parameter. Deterministic order.
std::vector<Case> ExpandCases(const Experiment& exp, const Registry& registry);

// "${VAR}" expansion from the environment (ARCS_SHARED_DIR defaults to the
// source tree's ../shared) and resolution relative to `base_dir`.
std::string ResolvePath(const std::string& path, const std::string& base_dir);

}  // namespace arcs
