#include "orchestration/table_spec.h"

#include "orchestration/paths.h"
#include "orchestration/yaml_check.h"
#include "orchestration/yaml_decode.h"

#include <algorithm>
#include <filesystem>

namespace fs = std::filesystem;

namespace arcs {

namespace {

std::vector<GroupSpec> ParseGroups(const std::string& f, const YAML::Node& gs, const std::string& fld) {
  std::vector<GroupSpec> groups;
  if (!gs.IsSequence()) Fail(f, gs, fld + ".groups", "must be a list of {name, where}");
  for (size_t g = 0; g < gs.size(); ++g) {
    const std::string gf = fld + ".groups[" + std::to_string(g) + "]";
    CheckKeys(f, gs[g], gf, {"name", "where"});
    GroupSpec group;
    if (!gs[g]["name"]) Fail(f, gs[g], gf, "missing key 'name'");
    group.name = GetString(f, gs[g]["name"], gf + ".name");
    if (gs[g]["where"]) group.where = GetStringList(f, gs[g]["where"], gf + ".where");
    groups.push_back(group);
  }
  return groups;
}

// One `reference:` entry: a CSV of published values beside our metrics.
ReferenceSpec ParseReference(const std::string& f, const YAML::Node& rn, const std::string& rf,
                             const std::string& base) {
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
  return ref;
}

TableSpec ParseTable(const std::string& f, const YAML::Node& t, size_t i, const std::string& base) {
  const std::string fld = "tables[" + std::to_string(i) + "]";
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
  if (t["groups"]) spec.groups = ParseGroups(f, t["groups"], fld);
  if (t["reference"]) {
    std::vector<YAML::Node> refs;
    if (t["reference"].IsSequence())
      for (size_t r = 0; r < t["reference"].size(); ++r) refs.push_back(t["reference"][r]);
    else
      refs.push_back(t["reference"]);
    for (size_t r = 0; r < refs.size(); ++r) {
      const std::string rf = fld + ".reference" + (refs.size() > 1 ? "[" + std::to_string(r) + "]" : "");
      spec.references.push_back(ParseReference(f, refs[r], rf, base));
    }
  }
  return spec;
}

}  // namespace

std::vector<TableSpec> ParseTables(const std::string& f, const YAML::Node& node, const std::string& base) {
  if (!node.IsSequence()) Fail(f, node, "tables", "must be a list");
  std::vector<TableSpec> tables;
  for (size_t i = 0; i < node.size(); ++i) tables.push_back(ParseTable(f, node[i], i, base));
  return tables;
}

void OrderColumnsByMethods(const YAML::Node& doc, std::vector<TableSpec>* specs) {
  std::vector<std::string> names;
  if (doc["methods"] && doc["methods"].IsSequence())
    for (const auto& m : doc["methods"])
      if (m.IsMap() && m["name"] && m["name"].IsScalar()) names.push_back(m["name"].Scalar());
  for (auto& t : *specs)
    if (t.columns == "method") t.column_order = names;
}

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

}  // namespace arcs
