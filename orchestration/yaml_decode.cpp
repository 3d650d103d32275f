#include "orchestration/yaml_decode.h"

#include "framework/util/suggest.h"

#include <algorithm>
#include <charconv>
#include <cmath>

namespace arcs {

std::string MarkOf(const std::string& file, const YAML::Node& node) {
  if (node.IsDefined() && node.Mark().line >= 0) return file + ":" + std::to_string(node.Mark().line + 1);
  return file + " (--set override)";
}

void Fail(const std::string& file, const YAML::Node& node, const std::string& field, const std::string& msg) {
  throw ExperimentError(MarkOf(file, node) + ": " + (field.empty() ? "" : field + ": ") + msg);
}

void CheckKeys(const std::string& file, const YAML::Node& node, const std::string& field,
               const std::vector<std::string>& allowed) {
  if (!node.IsMap()) Fail(file, node, field, "must be a mapping");
  for (const auto& kv : node) {
    const std::string key = kv.first.as<std::string>();
    if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
      std::string valid;
      for (const auto& a : allowed) valid += (valid.empty() ? "" : ", ") + a;
      Fail(file, kv.first, field, "unknown key '" + key + "'" + DidYouMean(key, allowed) + "; valid keys: " + valid);
    }
  }
}

std::string GetString(const std::string& file, const YAML::Node& node, const std::string& field) {
  if (!node.IsScalar()) Fail(file, node, field, "must be a text value");
  return node.as<std::string>();
}

bool GetBool(const std::string& file, const YAML::Node& node, const std::string& field) {
  bool b;
  if (!node.IsScalar() || !YAML::convert<bool>::decode(node, b)) Fail(file, node, field, "must be true or false");
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
  const std::string& t = s;
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

std::vector<std::string> GetStringList(const std::string& file, const YAML::Node& node, const std::string& field) {
  std::vector<std::string> out;
  if (node.IsScalar()) {
    out.push_back(node.as<std::string>());
  } else if (node.IsSequence()) {
    for (size_t i = 0; i < node.size(); ++i) out.push_back(GetString(file, node[i], field + "[" + std::to_string(i) + "]"));
  } else {
    Fail(file, node, field, "must be a text value or a list of them");
  }
  return out;
}

}  // namespace arcs
