#include "orchestration/spec.h"

#include "orchestration/overrides.h"
#include "orchestration/yaml_check.h"
#include "framework/util/suggest.h"
#include "registry/plugin.h"

#include <algorithm>
#include <filesystem>
#include <set>

namespace fs = std::filesystem;

namespace arcs {

namespace {

// A stage as written: "name" or {stage: name, params: {...}}.
struct StageRef {
  std::string stage;
  YAML::Node params;  // undefined when not given
};

StageRef DecodeStageRef(const std::string& file, const YAML::Node& node, const std::string& field) {
  StageRef out;
  if (node.IsScalar()) {
    out.stage = node.as<std::string>();
  } else if (node.IsMap()) {
    CheckKeys(file, node, field, {"stage", "params"});
    if (!node["stage"]) Fail(file, node, field, "missing key 'stage'");
    out.stage = GetString(file, node["stage"], field + ".stage");
    if (node["params"]) out.params = node["params"];  // assigning a missing key's node throws InvalidNode
  } else {
    Fail(file, node, field, "must be a stage name or {stage: NAME, params: {...}}");
  }
  return out;
}

// The registered stage `name`; an unknown one fails at `at` with the
// registry's message (did you mean ...).
const StageInfo& KnownStage(const std::string& file, const YAML::Node& at, const std::string& field,
                            const std::string& name, const Registry& registry) {
  if (const StageInfo* info = registry.Find(name)) return *info;
  try {
    return registry.Get(name);
  } catch (const Error& e) {
    Fail(file, at, field, e.what());
  }
}

std::string UnknownParameter(const StageInfo& info, const std::string& key) {
  std::string valid;
  std::vector<std::string> names;
  for (const auto& ps : info.params.specs()) {
    valid += (valid.empty() ? "" : ", ") + ps.name;
    names.push_back(ps.name);
  }
  return "stage '" + info.name + "' has no parameter '" + key + "'" + DidYouMean(key, names) +
         (valid.empty() ? "; it takes none" : "; valid: " + valid);
}

StageSpec DecodeStageValue(const std::string& file, const YAML::Node& node, const std::string& field,
                           const Registry& registry);

// Decodes one value of a parameter according to its spec.
ParamValue DecodeValue(const std::string& file, const YAML::Node& node, const std::string& field,
                       const ParamSpec& spec, const Registry& registry, const std::string& stage) {
  ParamValue v;
  switch (spec.type) {
    case ParamType::kBool: v = GetBool(file, node, field); break;
    case ParamType::kInt: v = GetInt(file, node, field); break;
    case ParamType::kDouble: v = GetDouble(file, node, field); break;
    case ParamType::kString:
    case ParamType::kChoice: v = GetString(file, node, field); break;
    case ParamType::kStage: {
      StageSpec nested = DecodeStageValue(file, node, field, registry);
      const StageInfo& info = registry.Get(nested.stage);
      if (RoleName(info.role) != spec.stage_role)
        Fail(file, node, field,
             "'" + nested.stage + "' is a " + RoleName(info.role) + " stage; expected a stage of role " +
                 spec.stage_role);
      InheritNestedDefaults(spec, &nested);
      try {
        nested.params = registry.Resolve(nested.stage, nested.params);
      } catch (const Error& e) {
        Fail(file, node, field, e.what());
      }
      v = std::make_shared<StageSpec>(std::move(nested));
      break;
    }
  }
  try {
    spec.CheckValue(v);
  } catch (const OptionError& e) {
    Fail(file, node, field, std::string("stage '") + stage + "': " + e.what() + " — " + spec.doc);
  }
  return v;
}

// A nested stage: "name" or {stage: name, params: {...}}; no sweeps inside.
StageSpec DecodeStageValue(const std::string& file, const YAML::Node& node, const std::string& field,
                           const Registry& registry) {
  StageSpec out;
  const StageRef ref = DecodeStageRef(file, node, field);
  out.stage = ref.stage;
  const YAML::Node params = ref.params;
  const StageInfo* info = &KnownStage(file, node, field, out.stage, registry);
  if (params && !params.IsNull()) {
    if (!params.IsMap()) Fail(file, params, field + ".params", "must be a mapping");
    for (const auto& kv : params) {
      const std::string key = kv.first.as<std::string>();
      const ParamSpec* spec = info->params.Find(key);
      const std::string pf = field + ".params." + key;
      if (!spec) Fail(file, kv.first, pf, UnknownParameter(*info, key));
      if (kv.second.IsSequence() && spec->type != ParamType::kStage)
        Fail(file, kv.second, pf, "sweeps inside a nested stage are not supported; sweep the outer "
                                  "parameter with a list of complete stage specs instead");
      out.params.Set(key, DecodeValue(file, kv.second, pf, *spec, registry, out.stage));
    }
  }
  return out;
}

// A pipeline stage entry with possible sweeps.
StageEntry DecodeStageEntry(const std::string& file, const YAML::Node& node, const std::string& field,
                            const Registry& registry, const std::vector<Role>& roles) {
  StageEntry e;
  const StageRef ref = DecodeStageRef(file, node, field);
  e.stage = ref.stage;
  const YAML::Node params = ref.params;
  e.where = MarkOf(file, node);
  const StageInfo* info = &KnownStage(file, node.IsMap() ? node["stage"] : node, field + ".stage", e.stage, registry);
  if (!roles.empty() && std::find(roles.begin(), roles.end(), info->role) == roles.end()) {
    std::string r;
    for (Role x : roles) r += (r.empty() ? "" : " or ") + std::string(RoleName(x));
    Fail(file, node, field, "'" + e.stage + "' is a " + RoleName(info->role) + " stage; here a stage of role " +
                                r + " is expected");
  }
  if (params && !params.IsNull()) {
    if (!params.IsMap()) Fail(file, params, field + ".params", "must be a mapping");
    for (const auto& kv : params) {
      const std::string key = kv.first.as<std::string>();
      const std::string pf = field + ".params." + key;
      const ParamSpec* spec = info->params.Find(key);
      if (!spec) Fail(file, kv.first, pf, UnknownParameter(*info, key));
      std::vector<ParamValue> values;
      if (kv.second.IsSequence()) {
        if (kv.second.size() == 0) Fail(file, kv.second, pf, "an empty sweep list");
        for (size_t i = 0; i < kv.second.size(); ++i)
          values.push_back(DecodeValue(file, kv.second[i], pf + "[" + std::to_string(i) + "]", *spec, registry,
                                       e.stage));
      } else {
        values.push_back(DecodeValue(file, kv.second, pf, *spec, registry, e.stage));
      }
      e.values.emplace_back(key, std::move(values));
    }
  }
  return e;
}

std::vector<PipelineSpec> DecodePipelines(const std::string& file, const YAML::Node& node,
                                          const std::string& field, const Registry& registry,
                                          const std::vector<Role>& roles) {
  std::vector<PipelineSpec> out;
  if (!node.IsSequence()) Fail(file, node, field, "must be a list of {name, pipeline}");
  std::set<std::string> names;
  for (size_t i = 0; i < node.size(); ++i) {
    const std::string f = field + "[" + std::to_string(i) + "]";
    const YAML::Node n = node[i];
    CheckKeys(file, n, f, {"name", "pipeline"});
    PipelineSpec p;
    if (!n["pipeline"]) Fail(file, n, f, "missing key 'pipeline'");
    const YAML::Node pl = n["pipeline"];
    if (!pl.IsSequence() || pl.size() == 0) Fail(file, pl, f + ".pipeline", "must be a non-empty list of stages");
    for (size_t j = 0; j < pl.size(); ++j)
      p.stages.push_back(DecodeStageEntry(file, pl[j], f + ".pipeline[" + std::to_string(j) + "]", registry, roles));
    p.name = n["name"] ? GetString(file, n["name"], f + ".name") : p.stages.front().stage;
    if (!names.insert(p.name).second) Fail(file, n, f + ".name", "duplicate name '" + p.name + "'");
    out.push_back(std::move(p));
  }
  return out;
}

NormalizeSpec DecodeNormalize(const std::string& f, const YAML::Node& n, const std::string& fld) {
  NormalizeSpec out;
  if (n.IsScalar()) {
    out.enabled = GetBool(f, n, fld);
    return out;
  }
  CheckKeys(f, n, fld, {"enabled", "longest_side", "center", "random_rotation", "rotation_seed"});
  if (n["enabled"]) out.enabled = GetBool(f, n["enabled"], fld + ".enabled");
  if (n["longest_side"]) {
    out.longest_side = GetDouble(f, n["longest_side"], fld + ".longest_side");
    if (!(out.longest_side > 0)) Fail(f, n["longest_side"], fld + ".longest_side", "must be > 0");
  }
  if (n["center"]) out.center = GetBool(f, n["center"], fld + ".center");
  if (n["random_rotation"]) out.random_rotation = GetBool(f, n["random_rotation"], fld + ".random_rotation");
  if (n["rotation_seed"]) out.rotation_seed = GetInt(f, n["rotation_seed"], fld + ".rotation_seed");
  return out;
}

// A dataset's items: `files` (paths or globs, each matching at least one
// file) then `shapes` (built-in shapes or curves, by the dataset's kind).
std::vector<DatasetItem> DecodeItems(const std::string& f, const YAML::Node& d, const std::string& fld,
                                     DatasetKind kind, const std::string& base) {
  std::vector<DatasetItem> items;
  if (d["files"]) {
    const auto pats = GetStringList(f, d["files"], fld + ".files");
    for (size_t j = 0; j < pats.size(); ++j) {
      const YAML::Node at = d["files"].IsSequence() ? d["files"][j] : d["files"];
      std::string resolved;
      try {
        resolved = ResolvePath(pats[j], base);
      } catch (const Error& e) {
        Fail(f, at, fld + ".files", e.what());
      }
      const auto matched = Glob(resolved);
      if (matched.empty()) Fail(f, at, fld + ".files", "'" + pats[j] + "' matches no file (looked for " + resolved + ")");
      for (const auto& m : matched) items.push_back(FileItem(kind, m));
    }
  }
  if (d["shapes"]) {
    for (const auto& s : GetStringList(f, d["shapes"], fld + ".shapes")) {
      try {
        items.push_back(BuiltinItem(kind, s));
      } catch (const Error& e) {
        Fail(f, d["shapes"], fld + ".shapes", e.what());
      }
    }
  }
  return items;
}

DatasetSpec DecodeDataset(const std::string& f, const YAML::Node& d, const std::string& fld, size_t i,
                          const std::string& base, std::set<std::string>* names) {
  CheckKeys(f, d, fld, {"name", "kind", "files", "shapes", "reference", "normalize"});
  DatasetSpec spec;
  spec.name = d["name"] ? GetString(f, d["name"], fld + ".name") : "dataset" + std::to_string(i);
  if (!names->insert(spec.name).second) Fail(f, d, fld + ".name", "duplicate dataset name '" + spec.name + "'");
  if (!d["files"] && !d["shapes"]) Fail(f, d, fld, "needs 'files' (paths or globs) or 'shapes' (built-in shapes)");
  if (d["kind"]) {
    const std::string k = GetString(f, d["kind"], fld + ".kind");
    if (!ParseDatasetKind(k, &spec.kind))
      Fail(f, d["kind"], fld + ".kind",
           "must be 'mesh' (files are meshes), 'points' (files are point clouds) or 'curves' (2D polylines), got '" + k +
               "'");
  }
  if (d["reference"]) {
    if (spec.kind != DatasetKind::kPoints)
      Fail(f, d["reference"], fld + ".reference", "only a 'kind: points' dataset takes a reference mesh");
    const std::string r = GetString(f, d["reference"], fld + ".reference");
    try {
      spec.reference = ResolvePath(r, base);
    } catch (const Error& e) {
      Fail(f, d["reference"], fld + ".reference", e.what());
    }
    if (!fs::exists(spec.reference))
      Fail(f, d["reference"], fld + ".reference", "'" + r + "' does not exist (looked for " + spec.reference + ")");
  }
  if (d["shapes"] && spec.kind == DatasetKind::kPoints)
    Fail(f, d["shapes"], fld + ".shapes", "built-in shapes are meshes; a 'kind: points' dataset needs 'files'");
  spec.items = DecodeItems(f, d, fld, spec.kind, base);
  if (d["normalize"]) spec.normalize = DecodeNormalize(f, d["normalize"], fld + ".normalize");
  return spec;
}

std::vector<DatasetSpec> DecodeDatasets(const std::string& f, const YAML::Node& doc, const std::string& base) {
  if (!doc["datasets"]) Fail(f, doc, "datasets", "missing: an experiment needs at least one dataset");
  const YAML::Node ds = doc["datasets"];
  if (!ds.IsSequence() || ds.size() == 0) Fail(f, ds, "datasets", "must be a non-empty list");
  std::vector<DatasetSpec> out;
  std::set<std::string> names;
  for (size_t i = 0; i < ds.size(); ++i)
    out.push_back(DecodeDataset(f, ds[i], "datasets[" + std::to_string(i) + "]", i, base, &names));
  return out;
}

// Plugins first: their stages may be named in the pipelines.
std::vector<std::string> LoadPlugins(const std::string& f, const YAML::Node& node, const std::string& base,
                                     Registry& registry) {
  std::vector<std::string> out;
  const auto list = GetStringList(f, node, "plugins");
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string p = ResolvePath(list[i], base);
    try {
      LoadPlugin(registry, p);
    } catch (const Error& e) {
      Fail(f, node.IsSequence() ? node[i] : node, "plugins[" + std::to_string(i) + "]", e.what());
    }
    out.push_back(p);
  }
  return out;
}

std::vector<StageEntry> DecodeMetrics(const std::string& f, const YAML::Node& m, const Registry& registry) {
  if (!m.IsSequence()) Fail(f, m, "metrics", "must be a list of evaluator stages");
  std::vector<StageEntry> out;
  for (size_t i = 0; i < m.size(); ++i) {
    StageEntry e = DecodeStageEntry(f, m[i], "metrics[" + std::to_string(i) + "]", registry, {Role::kEvaluator});
    for (const auto& [k, v] : e.values)
      if (v.size() > 1) Fail(f, m[i], "metrics[" + std::to_string(i) + "].params." + k, "metrics cannot be swept");
    out.push_back(std::move(e));
  }
  return out;
}

// The document: parsed, structure-checked, overridden.
YAML::Node ReadDocument(const std::string& path, const std::vector<std::string>& overrides) {
  if (!fs::is_regular_file(path)) throw ExperimentError(path + ": experiment file not found");
  YAML::Node doc;
  try {
    doc = YAML::LoadFile(path);
  } catch (const YAML::ParserException& e) {
    throw ExperimentError(path + ":" + std::to_string(e.mark.line + 1) + ":" + std::to_string(e.mark.column + 1) +
                          ": YAML syntax error: " + e.msg);
  } catch (const YAML::Exception& e) {
    throw ExperimentError(path + ": cannot read YAML: " + e.msg);
  }
  if (!doc.IsMap()) throw ExperimentError(path + ":1: an experiment must be a YAML mapping");
  CheckYamlStructure(path, doc);
  for (const auto& o : overrides) ApplyOverride(doc, o);
  return doc;
}

Experiment LoadExperimentImpl(const std::string& path, const std::vector<std::string>& overrides,
                              Registry& registry) {
  Experiment exp;
  exp.file = path;
  YAML::Node doc = ReadDocument(path, overrides);
  const std::string& f = path;
  const std::string base = fs::path(path).parent_path().string();

  CheckKeys(f, doc, "", {"name", "description", "seed", "method_seed", "case_timeout_s", "save_outputs", "plugins", "datasets",
                         "inputs", "methods", "metrics", "tables"});
  exp.name = doc["name"] ? GetString(f, doc["name"], "name") : fs::path(path).stem().string();
  if (doc["description"]) exp.description = GetString(f, doc["description"], "description");
  if (doc["seed"]) {
    const std::int64_t s = GetInt(f, doc["seed"], "seed");
    if (s < 0) Fail(f, doc["seed"], "seed", "must be >= 0");
    exp.seed = static_cast<std::uint64_t>(s);
  }
  if (doc["method_seed"]) {
    const std::string m = GetString(f, doc["method_seed"], "method_seed");
    if (m != "per_method" && m != "shared")
      Fail(f, doc["method_seed"], "method_seed", "'" + m + "' is not per_method (the default) or shared");
    exp.shared_method_seed = m == "shared";
  }
  if (doc["save_outputs"]) exp.save_outputs = GetBool(f, doc["save_outputs"], "save_outputs");
  if (doc["case_timeout_s"]) {
    exp.case_timeout_s = GetDouble(f, doc["case_timeout_s"], "case_timeout_s");
    if (exp.case_timeout_s < 0) Fail(f, doc["case_timeout_s"], "case_timeout_s", "must be >= 0 (0 = none)");
  }
  if (doc["plugins"]) exp.plugins = LoadPlugins(f, doc["plugins"], base, registry);
  exp.datasets = DecodeDatasets(f, doc, base);
  if (doc["inputs"])
    exp.inputs = DecodePipelines(f, doc["inputs"], "inputs", registry,
                                 {Role::kSdfSampler, Role::kSdfModifier, Role::kPointSampler, Role::kPointModifier,
                                  Role::kVoxelizer});
  if (!doc["methods"]) Fail(f, doc, "methods", "missing: an experiment needs at least one method");
  exp.methods = DecodePipelines(f, doc["methods"], "methods", registry, {});
  if (doc["metrics"]) exp.metrics = DecodeMetrics(f, doc["metrics"], registry);
  ValidatePipelines(exp, registry);
  if (doc["tables"]) {
    exp.tables = ParseTables(f, doc["tables"], base);
    OrderColumnsByMethods(doc, &exp.tables);
  }
  exp.resolved = YAML::Clone(doc);
  return exp;
}
}  // namespace

void ValidatePipelines(const Experiment& exp, const Registry& registry) {
  // The stage contract's data-flow check (Registry::CheckPipeline): every
  // input pipeline followed by every method and the metrics, for each kind
  // of dataset item (what a case starts with, and its dimension).
  struct Start {
    Slots slots;
    int dim;
  };
  std::vector<Start> starts;
  for (const auto& ds : exp.datasets) {
    Start st{Slots{Slot::kReference}, 3};
    if (ds.kind == DatasetKind::kCurves) st.dim = 2;
    if (ds.kind == DatasetKind::kPoints)
      st = Start{ds.reference.empty() ? Slots{Slot::kPoints} : Slots{Slot::kPoints, Slot::kReference}, 3};
    bool seen = false;
    for (const auto& o : starts) seen |= o.slots == st.slots && o.dim == st.dim;
    if (!seen) starts.push_back(st);
  }
  const PipelineSpec no_input;
  for (const auto& st : starts)
    for (const auto* in : exp.inputs.empty() ? std::vector<const PipelineSpec*>{&no_input} : [&] {
           std::vector<const PipelineSpec*> v;
           for (const auto& p : exp.inputs) v.push_back(&p);
           return v;
         }())
      for (const auto& m : exp.methods) {
        std::vector<const StageEntry*> entries;
        for (const auto& e : in->stages) entries.push_back(&e);
        for (const auto& e : m.stages) entries.push_back(&e);
        for (const auto& e : exp.metrics) entries.push_back(&e);
        std::vector<std::string> names;
        for (const auto* e : entries) names.push_back(e->stage);
        try {
          registry.CheckPipeline(names, st.slots, st.dim, [&](std::size_t i) { return entries[i]->where; });
        } catch (const ExperimentError&) {
          throw;
        } catch (const Error& e) {
          throw ExperimentError(std::string(e.what()) + " (input '" + in->name + "', method '" + m.name + "')");
        }
      }
}

// Any yaml-cpp exception the decoder did not turn into a located error (a
// node used as the wrong kind) still ends as an ExperimentError naming the file.
Experiment LoadExperiment(const std::string& path, const std::vector<std::string>& overrides,
                          Registry& registry) {
  try {
    return LoadExperimentImpl(path, overrides, registry);
  } catch (const YAML::Exception& e) {
    throw ExperimentError(path + (e.mark.line >= 0 ? ":" + std::to_string(e.mark.line + 1) : std::string()) +
                          ": " + e.msg);
  }
}

}  // namespace arcs
