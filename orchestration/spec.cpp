#include "orchestration/spec.h"
#include "orchestration/yaml_check.h"

#include "orchestration/version.h"
#include "framework/util/rng.h"
#include "framework/planar/curves.h"
#include "registry/plugin.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fnmatch.h>
#include <functional>
#include <set>
#include <sstream>

namespace fs = std::filesystem;

namespace arcs {

namespace {

// Location-aware failure: "file:line: field: message".
[[noreturn]] void Fail(const std::string& file, const YAML::Node& node, const std::string& field,
                       const std::string& msg) {
  std::string where = file;
  if (node.IsDefined() && node.Mark().line >= 0) {
    where += ":" + std::to_string(node.Mark().line + 1);
  } else {
    where += " (--set override)";
  }
  throw ExperimentError(where + ": " + (field.empty() ? "" : field + ": ") + msg);
}

std::string MarkOf(const std::string& file, const YAML::Node& node) {
  if (node.IsDefined() && node.Mark().line >= 0) return file + ":" + std::to_string(node.Mark().line + 1);
  return file + " (--set override)";
}

void CheckKeys(const std::string& file, const YAML::Node& node, const std::string& field,
               const std::vector<std::string>& allowed) {
  if (!node.IsMap()) Fail(file, node, field, "must be a mapping");
  for (const auto& kv : node) {
    const std::string key = kv.first.as<std::string>();
    if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
      std::string valid, best;
      int best_d = 1 << 30;
      for (const auto& a : allowed) {
        valid += (valid.empty() ? "" : ", ") + a;
        const int d = EditDistance(key, a);
        if (d < best_d) best_d = d, best = a;
      }
      std::string msg = "unknown key '" + key + "'";
      if (best_d <= std::max<int>(2, static_cast<int>(key.size()) / 3)) msg += " (did you mean '" + best + "'?)";
      msg += "; valid keys: " + valid;
      Fail(file, kv.first, field, msg);
    }
  }
}

std::string GetString(const std::string& file, const YAML::Node& node, const std::string& field) {
  if (!node.IsScalar()) Fail(file, node, field, "must be a text value");
  return node.as<std::string>();
}

bool GetBool(const std::string& file, const YAML::Node& node, const std::string& field) {
  bool b;
  if (!node.IsScalar() || !YAML::convert<bool>::decode(node, b))
    Fail(file, node, field, "must be true or false");
  return b;
}

bool ParseInt64(const std::string& s, std::int64_t* out) {
  const char* b = s.data();
  const char* e = s.data() + s.size();
  if (b != e && *b == '+') ++b;
  auto r = std::from_chars(b, e, *out);
  return r.ec == std::errc() && r.ptr == e;
}

bool ParseDouble(const std::string& s, double* out) {
  std::string t = s;
  if (t == "inf" || t == ".inf" || t == "+inf" || t == "+.inf") { *out = INFINITY; return true; }
  if (t == "-inf" || t == "-.inf") { *out = -INFINITY; return true; }
  const char* b = t.data();
  const char* e = t.data() + t.size();
  if (b != e && *b == '+') ++b;
  auto r = std::from_chars(b, e, *out);
  return r.ec == std::errc() && r.ptr == e && std::isfinite(*out);
}

std::int64_t GetInt(const std::string& file, const YAML::Node& node, const std::string& field) {
  std::int64_t v;
  if (!node.IsScalar() || !ParseInt64(node.Scalar(), &v)) Fail(file, node, field, "must be an integer");
  return v;
}

double GetDouble(const std::string& file, const YAML::Node& node, const std::string& field) {
  double v;
  if (!node.IsScalar() || !ParseDouble(node.Scalar(), &v)) Fail(file, node, field, "must be a number");
  return v;
}

std::vector<std::string> GetStringList(const std::string& file, const YAML::Node& node,
                                       const std::string& field) {
  std::vector<std::string> out;
  if (node.IsScalar()) {
    out.push_back(node.as<std::string>());
  } else if (node.IsSequence()) {
    for (size_t i = 0; i < node.size(); ++i)
      out.push_back(GetString(file, node[i], field + "[" + std::to_string(i) + "]"));
  } else {
    Fail(file, node, field, "must be a text value or a list of them");
  }
  return out;
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
  YAML::Node params;
  if (node.IsScalar()) {
    out.stage = node.as<std::string>();
  } else if (node.IsMap()) {
    CheckKeys(file, node, field, {"stage", "params"});
    if (!node["stage"]) Fail(file, node, field, "missing key 'stage'");
    out.stage = GetString(file, node["stage"], field + ".stage");
    if (node["params"]) params = node["params"];  // assigning a missing key's node throws InvalidNode
  } else {
    Fail(file, node, field, "must be a stage name or {stage: NAME, params: {...}}");
  }
  const StageInfo* info = registry.Find(out.stage);
  if (!info) {
    try {
      registry.Get(out.stage);
    } catch (const Error& e) {
      Fail(file, node, field, e.what());
    }
  }
  if (params && !params.IsNull()) {
    if (!params.IsMap()) Fail(file, params, field + ".params", "must be a mapping");
    for (const auto& kv : params) {
      const std::string key = kv.first.as<std::string>();
      const ParamSpec* spec = info->params.Find(key);
      const std::string pf = field + ".params." + key;
      if (!spec) {
        try {
          ParamMap probe;
          probe.Set(key, false);
          registry.Resolve(out.stage, probe);
        } catch (const Error& e) {
          Fail(file, kv.first, pf, e.what());
        }
      }
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
  YAML::Node params;
  if (node.IsScalar()) {
    e.stage = node.as<std::string>();
  } else if (node.IsMap()) {
    CheckKeys(file, node, field, {"stage", "params"});
    if (!node["stage"]) Fail(file, node, field, "missing key 'stage'");
    e.stage = GetString(file, node["stage"], field + ".stage");
    if (node["params"]) params = node["params"];  // assigning a missing key's node throws InvalidNode
  } else {
    Fail(file, node, field, "must be a stage name or {stage: NAME, params: {...}}");
  }
  e.where = MarkOf(file, node);
  const StageInfo* info = registry.Find(e.stage);
  if (!info) {
    try {
      registry.Get(e.stage);
    } catch (const Error& err) {
      Fail(file, node.IsMap() ? node["stage"] : node, field + ".stage", err.what());
    }
  }
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
      if (!spec) {
        std::string valid, best;
        int best_d = 1 << 30;
        for (const auto& s : info->params.specs()) {
          valid += (valid.empty() ? "" : ", ") + s.name;
          const int d = EditDistance(key, s.name);
          if (d < best_d) best_d = d, best = s.name;
        }
        std::string msg = "stage '" + e.stage + "' has no parameter '" + key + "'";
        if (best_d <= 2) msg += " (did you mean '" + best + "'?)";
        msg += valid.empty() ? "; it takes none" : "; valid: " + valid;
        Fail(file, kv.first, pf, msg);
      }
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

std::string DefaultSharedDir() {
  return (fs::path(SourceDir()) / ".." / "shared").lexically_normal().string();
}

// Files matching a glob pattern (only the last path component may contain
// wildcards), sorted.
std::vector<std::string> Glob(const std::string& pattern) {
  const fs::path p(pattern);
  const std::string leaf = p.filename().string();
  if (leaf.find_first_of("*?[") == std::string::npos) {
    if (fs::is_regular_file(p)) return {p.string()};
    return {};
  }
  std::vector<std::string> out;
  std::error_code ec;
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  if (!fs::is_directory(dir, ec)) return {};
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    if (!e.is_regular_file()) continue;
    if (fnmatch(leaf.c_str(), e.path().filename().c_str(), 0) == 0) out.push_back(e.path().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

const std::vector<std::string> kBuiltinShapes = {"sphere", "torus", "knot", "two_tori"};

}  // namespace

std::string ResolvePath(const std::string& path, const std::string& base_dir) {
  std::string out;
  for (size_t i = 0; i < path.size(); ++i) {
    if (path[i] == '$' && i + 1 < path.size() && path[i + 1] == '{') {
      const size_t end = path.find('}', i);
      if (end == std::string::npos) throw Error("unterminated ${ in path '" + path + "'");
      const std::string var = path.substr(i + 2, end - i - 2);
      const char* val = std::getenv(var.c_str());
      if (val) out += val;
      else if (var == "ARCS_SHARED_DIR") out += DefaultSharedDir();
      else if (var == "ARCS_SOURCE_DIR") out += SourceDir();
      else throw Error("environment variable ${" + var + "} used in path '" + path + "' is not set");
      i = end;
    } else {
      out += path[i];
    }
  }
  fs::path p(out);
  if (p.is_relative() && !base_dir.empty()) p = fs::path(base_dir) / p;
  return p.lexically_normal().string();
}

std::string Case::Label() const {
  std::string s = item;
  for (const auto& [k, v] : params) {
    if (std::find(varying.begin(), varying.end(), k) != varying.end())
      s += " " + k.substr(k.rfind('.') + 1) + "=" + v;
  }
  return s + " | " + input + " | " + method;
}

namespace {
// A copy of a node built programmatically, so it carries no file mark and
// errors about it say "--set override" instead of a wrong line.
YAML::Node Unmarked(const YAML::Node& n) {
  if (n.IsScalar()) return YAML::Node(n.Scalar());
  if (n.IsSequence()) {
    YAML::Node out(YAML::NodeType::Sequence);
    for (const auto& e : n) out.push_back(Unmarked(e));
    return out;
  }
  if (n.IsMap()) {
    YAML::Node out(YAML::NodeType::Map);
    for (const auto& kv : n) out[kv.first.Scalar()] = Unmarked(kv.second);
    return out;
  }
  return YAML::Node();
}
}  // namespace

void ApplyOverride(YAML::Node& doc, const std::string& assignment) {
  const size_t eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw ExperimentError("--set " + assignment + ": expected path.to.key=value");
  const std::string path = assignment.substr(0, eq);
  YAML::Node value;
  try {
    const YAML::Node parsed = YAML::Load(assignment.substr(eq + 1));
    CheckYamlStructure("--set " + assignment.substr(0, eq), parsed);  // no cycle before Unmarked recurses
    value = Unmarked(parsed);
  } catch (const YAML::Exception& e) {
    throw ExperimentError("--set " + assignment + ": value is not valid YAML: " + e.msg);
  }
  std::vector<std::string> parts;
  std::stringstream ss(path);
  for (std::string part; std::getline(ss, part, '.');) parts.push_back(part);

  YAML::Node cur = doc;
  for (size_t i = 0; i < parts.size(); ++i) {
    const std::string& key = parts[i];
    const bool last = i + 1 == parts.size();
    if (cur.IsSequence()) {
      // A default-constructed YAML::Node is a defined null node (`!found`
      // is false), so "found" is its own flag: else a typo in a list
      // element's name was written into a detached node and silently lost.
      YAML::Node found;
      bool have = false;
      std::int64_t idx;
      if (ParseInt64(key, &idx) && idx >= 0 && static_cast<size_t>(idx) < cur.size()) {
        found = cur[static_cast<size_t>(idx)];
        have = true;
      } else {
        for (size_t j = 0; j < cur.size(); ++j) {
          YAML::Node el = cur[j];
          if (el.IsMap() && ((el["name"] && el["name"].IsScalar() && el["name"].Scalar() == key) ||
                             (el["stage"] && el["stage"].IsScalar() && el["stage"].Scalar() == key))) {
            found = el;
            have = true;
            break;
          }
          if (el.IsScalar() && el.as<std::string>() == key) {  // a bare stage name
            YAML::Node m;
            m["stage"] = key;
            cur[j] = m;
            found = cur[j];
            have = true;
            break;
          }
        }
        // Inside a method, "MC.marching_cubes" also looks into its pipeline.
      }
      if (!have) throw ExperimentError("--set " + assignment + ": no element named '" + key + "' in '" +
                                        path.substr(0, path.find(key)) + "'");
      if (last) throw ExperimentError("--set " + assignment + ": cannot replace a whole list element");
      cur.reset(found);
      continue;
    }
    if (!cur.IsMap() && !cur.IsNull())
      throw ExperimentError("--set " + assignment + ": '" + key + "' is below a plain value");
    if (!last) {
      if (cur[key]) {
        YAML::Node next = cur[key];
        cur.reset(next);
        continue;
      }
      if (cur["pipeline"]) {  // methods.MC.marching_cubes... → the pipeline
        YAML::Node pl = cur["pipeline"];
        cur.reset(pl);
        --i;
        continue;
      }
      if (cur["stage"]) {  // stage entry: look into params
        if (!cur["params"]) cur["params"] = YAML::Node(YAML::NodeType::Map);
        YAML::Node pr = cur["params"];
        cur.reset(pr);
        --i;
        continue;
      }
      YAML::Node fresh(YAML::NodeType::Map);
      cur[key] = fresh;
      YAML::Node next = cur[key];
      cur.reset(next);
      continue;
    }
    if (cur.IsMap() && cur["stage"] && !cur[key] && key != "stage" && key != "params") {
      if (!cur["params"]) cur["params"] = YAML::Node(YAML::NodeType::Map);
      cur["params"][key] = value;
    } else {
      cur[key] = value;
    }
  }
}

std::vector<TableSpec> ParseTables(const std::string& f, const YAML::Node& node, const std::string& base) {
  std::vector<TableSpec> tables;
  {
    const YAML::Node ts = node;
    if (!ts.IsSequence()) Fail(f, ts, "tables", "must be a list");
    for (size_t i = 0; i < ts.size(); ++i) {
      const std::string fld = "tables[" + std::to_string(i) + "]";
      const YAML::Node t = ts[i];
      CheckKeys(f, t, fld, {"name", "metrics", "rows", "columns", "aggregate", "groups", "reference", "format", "paired",
                            "failures"});
      TableSpec spec;
      spec.name = t["name"] ? GetString(f, t["name"], fld + ".name") : "table" + std::to_string(i);
      if (!t["metrics"]) Fail(f, t, fld, "missing key 'metrics'");
      spec.metrics = GetStringList(f, t["metrics"], fld + ".metrics");
      if (!t["rows"]) Fail(f, t, fld, "missing key 'rows'");
      spec.rows = GetString(f, t["rows"], fld + ".rows");
      if (t["columns"]) spec.columns = GetString(f, t["columns"], fld + ".columns");
      if (t["aggregate"]) {
        spec.aggregate = GetString(f, t["aggregate"], fld + ".aggregate");
        static const std::vector<std::string> aggs = {"mean", "median", "min", "max", "std", "count"};
        if (std::find(aggs.begin(), aggs.end(), spec.aggregate) == aggs.end())
          Fail(f, t["aggregate"], fld + ".aggregate", "must be one of mean|median|min|max|std|count");
      }
      if (t["format"]) spec.format = GetString(f, t["format"], fld + ".format");
      if (t["paired"]) spec.paired = GetBool(f, t["paired"], fld + ".paired");
      if (t["failures"]) spec.failures = GetBool(f, t["failures"], fld + ".failures");
      if (t["groups"]) {
        const YAML::Node gs = t["groups"];
        if (!gs.IsSequence()) Fail(f, gs, fld + ".groups", "must be a list of {name, where}");
        for (size_t g = 0; g < gs.size(); ++g) {
          const std::string gf = fld + ".groups[" + std::to_string(g) + "]";
          CheckKeys(f, gs[g], gf, {"name", "where"});
          GroupSpec group;
          if (!gs[g]["name"]) Fail(f, gs[g], gf, "missing key 'name'");
          group.name = GetString(f, gs[g]["name"], gf + ".name");
          if (gs[g]["where"]) group.where = GetStringList(f, gs[g]["where"], gf + ".where");
          spec.groups.push_back(group);
        }
      }
      if (t["reference"]) {
        const YAML::Node rs = t["reference"].IsSequence() ? t["reference"] : YAML::Node();
        std::vector<YAML::Node> refs;
        if (t["reference"].IsSequence())
          for (size_t r = 0; r < rs.size(); ++r) refs.push_back(rs[r]);
        else
          refs.push_back(t["reference"]);
        for (size_t r = 0; r < refs.size(); ++r) {
          const std::string rf = fld + ".reference" + (refs.size() > 1 ? "[" + std::to_string(r) + "]" : "");
          const YAML::Node rn = refs[r];
          CheckKeys(f, rn, rf, {"file", "match", "where", "columns"});
          ReferenceSpec ref;
          if (!rn["file"]) Fail(f, rn, rf, "missing key 'file'");
          try {
            ref.file = ResolvePath(GetString(f, rn["file"], rf + ".file"), base);
          } catch (const Error& e) {
            Fail(f, rn["file"], rf + ".file", e.what());
          }
          if (rn["match"]) {
            if (!rn["match"].IsMap()) Fail(f, rn["match"], rf + ".match", "must map reference columns to group|rows|a results column");
            for (const auto& kv : rn["match"])
              ref.match.emplace_back(kv.first.as<std::string>(), GetString(f, kv.second, rf + ".match"));
          }
          if (rn["where"]) ref.where = GetStringList(f, rn["where"], rf + ".where");
          if (!rn["columns"] || !rn["columns"].IsSequence()) Fail(f, rn, rf + ".columns", "must be a list of {metric, column, label}");
          for (size_t c = 0; c < rn["columns"].size(); ++c) {
            const YAML::Node cn = rn["columns"][c];
            const std::string cf = rf + ".columns[" + std::to_string(c) + "]";
            CheckKeys(f, cn, cf, {"metric", "column", "label"});
            if (!cn["metric"] || !cn["column"]) Fail(f, cn, cf, "needs 'metric' and 'column'");
            ReferenceColumn col;
            col.metric = GetString(f, cn["metric"], cf + ".metric");
            col.column = GetString(f, cn["column"], cf + ".column");
            col.label = cn["label"] ? GetString(f, cn["label"], cf + ".label") : col.column;
            ref.columns.push_back(col);
          }
          spec.references.push_back(ref);
        }
      }
      tables.push_back(std::move(spec));
    }
  }

  return tables;
}

namespace {
// Tables with columns "method" list the methods in the experiment's order
// (not in the order cases happened to finish).
void OrderColumnsByMethods(const YAML::Node& doc, std::vector<TableSpec>* specs) {
  std::vector<std::string> names;
  if (doc["methods"] && doc["methods"].IsSequence())
    for (const auto& m : doc["methods"])
      if (m.IsMap() && m["name"] && m["name"].IsScalar()) names.push_back(m["name"].Scalar());
  for (auto& t : *specs)
    if (t.columns == "method") t.column_order = names;
}
}  // namespace

std::vector<TableSpec> LoadTableSpecs(const std::string& path) {
  YAML::Node doc;
  try {
    doc = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw ExperimentError(path + ":" + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
  CheckYamlStructure(path, doc);
  if (!doc.IsMap() || !doc["tables"]) return {};
  std::vector<TableSpec> specs = ParseTables(path, doc["tables"], fs::path(path).parent_path().string());
  OrderColumnsByMethods(doc, &specs);
  return specs;
}

namespace {
Experiment LoadExperimentImpl(const std::string& path, const std::vector<std::string>& overrides,
                              Registry& registry);
}  // namespace

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

namespace {
Experiment LoadExperimentImpl(const std::string& path, const std::vector<std::string>& overrides,
                              Registry& registry) {
  Experiment exp;
  exp.file = path;
  if (!fs::is_regular_file(path)) throw ExperimentError(path + ": experiment file not found");
  YAML::Node doc;
  try {
    doc = YAML::LoadFile(path);
  } catch (const YAML::ParserException& e) {
    throw ExperimentError(path + ":" + std::to_string(e.mark.line + 1) + ":" +
                          std::to_string(e.mark.column + 1) + ": YAML syntax error: " + e.msg);
  } catch (const YAML::Exception& e) {
    throw ExperimentError(path + ": cannot read YAML: " + e.msg);
  }
  if (!doc.IsMap()) throw ExperimentError(path + ":1: an experiment must be a YAML mapping");
  CheckYamlStructure(path, doc);
  for (const auto& o : overrides) ApplyOverride(doc, o);
  const std::string& f = path;
  const std::string base = fs::path(path).parent_path().string();

  CheckKeys(f, doc, "", {"name", "description", "seed", "case_timeout_s", "save_outputs", "plugins", "datasets",
                         "inputs", "methods", "metrics", "tables"});
  exp.name = doc["name"] ? GetString(f, doc["name"], "name") : fs::path(path).stem().string();
  if (doc["description"]) exp.description = GetString(f, doc["description"], "description");
  if (doc["seed"]) {
    const std::int64_t s = GetInt(f, doc["seed"], "seed");
    if (s < 0) Fail(f, doc["seed"], "seed", "must be >= 0");
    exp.seed = static_cast<std::uint64_t>(s);
  }
  if (doc["save_outputs"]) exp.save_outputs = GetBool(f, doc["save_outputs"], "save_outputs");
  if (doc["case_timeout_s"]) {
    exp.case_timeout_s = GetDouble(f, doc["case_timeout_s"], "case_timeout_s");
    if (exp.case_timeout_s < 0) Fail(f, doc["case_timeout_s"], "case_timeout_s", "must be >= 0 (0 = none)");
  }

  // Plugins first: their stages may be named below.
  if (doc["plugins"]) {
    const auto list = GetStringList(f, doc["plugins"], "plugins");
    for (size_t i = 0; i < list.size(); ++i) {
      const std::string p = ResolvePath(list[i], base);
      try {
        LoadPlugin(registry, p);
      } catch (const Error& e) {
        Fail(f, doc["plugins"].IsSequence() ? doc["plugins"][i] : doc["plugins"],
             "plugins[" + std::to_string(i) + "]", e.what());
      }
      exp.plugins.push_back(p);
    }
  }

  // Datasets.
  if (!doc["datasets"]) Fail(f, doc, "datasets", "missing: an experiment needs at least one dataset");
  {
    const YAML::Node ds = doc["datasets"];
    if (!ds.IsSequence() || ds.size() == 0) Fail(f, ds, "datasets", "must be a non-empty list");
    std::set<std::string> names;
    for (size_t i = 0; i < ds.size(); ++i) {
      const std::string fld = "datasets[" + std::to_string(i) + "]";
      const YAML::Node d = ds[i];
      CheckKeys(f, d, fld, {"name", "kind", "files", "shapes", "reference", "normalize"});
      DatasetSpec spec;
      spec.name = d["name"] ? GetString(f, d["name"], fld + ".name") : "dataset" + std::to_string(i);
      if (!names.insert(spec.name).second) Fail(f, d, fld + ".name", "duplicate dataset name '" + spec.name + "'");
      if (!d["files"] && !d["shapes"]) Fail(f, d, fld, "needs 'files' (paths or globs) or 'shapes' (built-in shapes)");
      if (d["kind"]) {
        spec.kind = GetString(f, d["kind"], fld + ".kind");
        if (spec.kind != "mesh" && spec.kind != "points" && spec.kind != "curves")
          Fail(f, d["kind"], fld + ".kind",
               "must be 'mesh' (files are meshes), 'points' (files are point clouds) or 'curves' (2D polylines), got '" +
                   spec.kind + "'");
      }
      if (d["reference"]) {
        if (spec.kind != "points")
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
      if (d["shapes"] && spec.kind == "points")
        Fail(f, d["shapes"], fld + ".shapes", "built-in shapes are meshes; a 'kind: points' dataset needs 'files'");
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
          auto matched = Glob(resolved);
          if (matched.empty())
            Fail(f, at, fld + ".files", "'" + pats[j] + "' matches no file (looked for " + resolved + ")");
          spec.files.insert(spec.files.end(), matched.begin(), matched.end());
        }
      }
      if (d["shapes"] && spec.kind == "curves") {
        const auto names = BuiltinCurveNames();
        for (const auto& s : GetStringList(f, d["shapes"], fld + ".shapes")) {
          if (std::find(names.begin(), names.end(), s) == names.end()) {
            std::string valid;
            for (const auto& b : names) valid += (valid.empty() ? "" : ", ") + b;
            Fail(f, d["shapes"], fld + ".shapes", "unknown built-in curve '" + s + "'; valid: " + valid);
          }
          spec.files.push_back("curve:" + s);
        }
      } else if (d["shapes"]) {
        for (const auto& s : GetStringList(f, d["shapes"], fld + ".shapes")) {
          if (std::find(kBuiltinShapes.begin(), kBuiltinShapes.end(), s) == kBuiltinShapes.end()) {
            std::string valid;
            for (const auto& b : kBuiltinShapes) valid += (valid.empty() ? "" : ", ") + b;
            Fail(f, d["shapes"], fld + ".shapes", "unknown built-in shape '" + s + "'; valid: " + valid);
          }
          spec.files.push_back("shape:" + s);
        }
      }
      if (d["normalize"]) {
        const YAML::Node n = d["normalize"];
        if (n.IsScalar()) {
          spec.normalize.enabled = GetBool(f, n, fld + ".normalize");
        } else {
          CheckKeys(f, n, fld + ".normalize", {"enabled", "longest_side", "center", "random_rotation", "rotation_seed"});
          if (n["enabled"]) spec.normalize.enabled = GetBool(f, n["enabled"], fld + ".normalize.enabled");
          if (n["longest_side"]) {
            spec.normalize.longest_side = GetDouble(f, n["longest_side"], fld + ".normalize.longest_side");
            if (!(spec.normalize.longest_side > 0))
              Fail(f, n["longest_side"], fld + ".normalize.longest_side", "must be > 0");
          }
          if (n["center"]) spec.normalize.center = GetBool(f, n["center"], fld + ".normalize.center");
          if (n["random_rotation"])
            spec.normalize.random_rotation = GetBool(f, n["random_rotation"], fld + ".normalize.random_rotation");
          if (n["rotation_seed"]) spec.normalize.rotation_seed = GetInt(f, n["rotation_seed"], fld + ".normalize.rotation_seed");
        }
      }
      exp.datasets.push_back(std::move(spec));
    }
  }

  if (doc["inputs"])
    exp.inputs = DecodePipelines(f, doc["inputs"], "inputs", registry, {Role::kSdfSampler, Role::kSdfModifier, Role::kPointSampler, Role::kPointModifier, Role::kVoxelizer});
  if (!doc["methods"]) Fail(f, doc, "methods", "missing: an experiment needs at least one method");
  exp.methods = DecodePipelines(f, doc["methods"], "methods", registry, {});
  if (doc["metrics"]) {
    const YAML::Node m = doc["metrics"];
    if (!m.IsSequence()) Fail(f, m, "metrics", "must be a list of evaluator stages");
    for (size_t i = 0; i < m.size(); ++i) {
      StageEntry e = DecodeStageEntry(f, m[i], "metrics[" + std::to_string(i) + "]", registry, {Role::kEvaluator});
      for (const auto& [k, v] : e.values)
        if (v.size() > 1) Fail(f, m[i], "metrics[" + std::to_string(i) + "].params." + k, "metrics cannot be swept");
      exp.metrics.push_back(std::move(e));
    }
  }

  if (doc["tables"]) {
    exp.tables = ParseTables(f, doc["tables"], base);
    OrderColumnsByMethods(doc, &exp.tables);
  }

  exp.resolved = YAML::Clone(doc);
  return exp;
}
}  // namespace

namespace {

// Cartesian product of a pipeline's sweeps, each resolved against the registry.
std::vector<std::vector<StageSpec>> ExpandPipeline(const PipelineSpec& p, const Registry& registry) {
  std::vector<std::vector<StageSpec>> out(1);
  for (const auto& entry : p.stages) {
    // A value swept twice would run the same case twice under one id: refused.
    for (const auto& [key, values] : entry.values) {
      std::map<std::string, size_t> seen;
      for (size_t i = 0; i < values.size(); ++i) {
        const std::string v = FormatParamValue(values[i]);
        if (!seen.emplace(v, i).second)
          throw ExperimentError(entry.where + ": " + p.name + "." + entry.stage + ".params." + key + ": sweep value " +
                                v + " is listed twice (at [" + std::to_string(seen[v]) + "] and [" + std::to_string(i) +
                                "]); each value runs once, remove the repeat");
      }
    }
    // Product over this entry's parameters.
    std::vector<ParamMap> variants(1);
    for (const auto& [key, values] : entry.values) {
      std::vector<ParamMap> next;
      for (const auto& base : variants)
        for (const auto& v : values) {
          ParamMap m = base;
          m.Set(key, v);
          next.push_back(std::move(m));
        }
      variants = std::move(next);
    }
    std::vector<std::vector<StageSpec>> next;
    for (const auto& prefix : out)
      for (const auto& given : variants) {
        auto seq = prefix;
        ParamMap resolved;
        try {
          resolved = registry.Resolve(entry.stage, given);
        } catch (const Error& e) {
          throw ExperimentError(entry.where + ": " + e.what());
        }
        seq.push_back(StageSpec{entry.stage, resolved});
        next.push_back(std::move(seq));
      }
    out = std::move(next);
  }
  return out;
}

void AddParamColumns(const std::vector<StageSpec>& stages,
                     std::vector<std::pair<std::string, std::string>>* cols) {
  std::map<std::string, int> seen;
  for (const auto& s : stages) {
    const int k = seen[s.stage]++;
    const std::string prefix = k == 0 ? s.stage : s.stage + "#" + std::to_string(k + 1);
    for (const auto& [name, v] : s.params.items()) cols->emplace_back(prefix + "." + name, FormatParamValue(v));
  }
}

std::string CanonicalStages(const std::vector<StageSpec>& stages) {
  std::string s;
  for (const auto& st : stages) {
    s += st.stage + "(";
    for (const auto& [k, v] : st.params.items()) s += k + "=" + FormatParamValue(v) + ";";
    s += ")";
  }
  return s;
}

std::string Hex16(std::uint64_t x) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(x));
  return buf;
}

}  // namespace

static std::uint64_t MaxCases() {
  if (const char* v = std::getenv("ARCS_MAX_CASES")) {
    char* end = nullptr;
    const unsigned long long x = std::strtoull(v, &end, 10);
    if (*v && !*end && x > 0) return x;
    throw ExperimentError(std::string("$ARCS_MAX_CASES = '") + v + "' is not a positive integer");
  }
  return 100000;
}

std::vector<Case> ExpandCases(const Experiment& exp, const Registry& registry) {
  // Count first (saturating), so a huge sweep is an error, not an out-of-memory.
  {
    const std::uint64_t cap = MaxCases(), big = std::uint64_t(1) << 62;
    auto mul = [&](std::uint64_t a, std::uint64_t b) { return a == 0 || b <= big / a ? a * b : big; };
    auto variants = [&](const PipelineSpec& p) {
      std::uint64_t n = 1;
      for (const auto& e : p.stages)
        for (const auto& kv : e.values) n = mul(n, kv.second.size());
      return n;
    };
    std::uint64_t items = 0, ins = exp.inputs.empty() ? 1 : 0, ms = 0;
    for (const auto& ds : exp.datasets) items = std::min(big, items + ds.files.size());
    for (const auto& in : exp.inputs) ins = std::min(big, ins + variants(in));
    for (const auto& m : exp.methods) ms = std::min(big, ms + variants(m));
    const std::uint64_t total = mul(mul(items, ins), ms);
    if (total > cap)
      throw ExperimentError(exp.file + ": the experiment expands to " + (total >= big ? "more than 4e18" : std::to_string(total)) +
                            " cases (" + std::to_string(items) + " items x " + std::to_string(ins) + " input variants x " +
                            std::to_string(ms) + " method variants), more than the limit of " + std::to_string(cap) +
                            "; sweep fewer values, or raise the limit with ARCS_MAX_CASES");
  }
  std::vector<Case> cases;
  std::vector<std::pair<std::string, std::vector<std::vector<StageSpec>>>> inputs;
  if (exp.inputs.empty()) inputs.push_back({"none", {{}}});
  for (const auto& in : exp.inputs) inputs.push_back({in.name, ExpandPipeline(in, registry)});
  std::vector<std::pair<std::string, std::vector<std::vector<StageSpec>>>> methods;
  for (const auto& m : exp.methods) methods.push_back({m.name, ExpandPipeline(m, registry)});
  std::vector<StageSpec> metrics;
  for (const auto& e : exp.metrics) {
    ParamMap given;
    for (const auto& [k, v] : e.values) given.Set(k, v.front());
    metrics.push_back(StageSpec{e.stage, registry.Resolve(e.stage, given)});
  }
  const std::string metric_key = CanonicalStages(metrics);

  for (const auto& ds : exp.datasets) {
    for (const auto& file : ds.files) {
      for (const auto& [in_name, in_variants] : inputs) {
        for (const auto& in_stages : in_variants) {
          for (const auto& [m_name, m_variants] : methods) {
            for (const auto& m_stages : m_variants) {
              Case c;
              c.dataset = ds.name;
              c.item_path = file;
              c.item = file.rfind("shape:", 0) == 0 || file.rfind("curve:", 0) == 0 ? file.substr(6)
                                                                                     : fs::path(file).stem().string();
              c.normalize = ds.normalize;
              c.kind = ds.kind;
              c.reference_path = ds.reference;
              c.input = in_name;
              c.input_stages = in_stages;
              c.method = m_name;
              c.method_stages = m_stages;
              c.metric_stages = metrics;
              c.seed = exp.seed;
              AddParamColumns(in_stages, &c.params);
              AddParamColumns(m_stages, &c.params);
              const auto& nz = ds.normalize;
              const std::string key =
                  "item=" + file + (ds.kind == "points" ? "|points|ref=" + ds.reference : std::string()) + "|norm=" + std::to_string(nz.enabled) + "," + std::to_string(nz.longest_side) + "," +
                  std::to_string(nz.center) + "," + std::to_string(nz.random_rotation) + "," +
                  std::to_string(nz.rotation_seed) + "|input=" + in_name + ":" + CanonicalStages(in_stages) +
                  "|method=" + m_name + ":" + CanonicalStages(m_stages) + "|metrics=" + metric_key +
                  "|seed=" + std::to_string(exp.seed);
              c.id = Hex16(Fnv1a64(key));
              cases.push_back(std::move(c));
            }
          }
        }
      }
    }
  }
  // The same case twice (a file listed twice, overlapping globs): refused.
  {
    std::map<std::string, size_t> seen;
    for (size_t i = 0; i < cases.size(); ++i) {
      const auto [it, fresh] = seen.emplace(cases[i].id, i);
      if (!fresh)
        throw ExperimentError(exp.file + ": case " + cases[i].id + " appears twice (" + cases[it->second].item_path +
                              " | " + cases[i].input + " | " + cases[i].method +
                              "): an item listed twice in a dataset, or two datasets with the same files? each case runs once");
    }
  }
  // Which parameter columns vary (shown in progress labels).
  std::map<std::string, std::set<std::string>> values;
  for (const auto& c : cases)
    for (const auto& [k, v] : c.params) values[k].insert(v);
  std::vector<std::string> varying;
  for (const auto& [k, vs] : values)
    if (vs.size() > 1) varying.push_back(k);
  for (auto& c : cases) c.varying = varying;
  return cases;
}

}  // namespace arcs
