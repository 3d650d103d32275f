#include "orchestration/overrides.h"

#include "orchestration/yaml_check.h"
#include "orchestration/yaml_decode.h"

#include <cstdint>
#include <sstream>
#include <vector>

namespace arcs {

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

}  // namespace arcs
