#include "registry/param.h"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace arcs {

const char* ParamTypeName(ParamType t) {
  switch (t) {
    case ParamType::kBool: return "bool";
    case ParamType::kInt: return "int";
    case ParamType::kDouble: return "float";
    case ParamType::kString: return "string";
    case ParamType::kChoice: return "choice";
    case ParamType::kStage: return "stage";
  }
  return "?";
}

void ParamMap::Set(const std::string& name, ParamValue v) {
  for (auto& [k, val] : items_) {
    if (k == name) {
      val = std::move(v);
      return;
    }
  }
  items_.emplace_back(name, std::move(v));
}

bool ParamMap::Has(const std::string& name) const {
  for (const auto& [k, v] : items_)
    if (k == name) return true;
  return false;
}

const ParamValue& ParamMap::Get(const std::string& name) const {
  for (const auto& [k, v] : items_)
    if (k == name) return v;
  throw Error("internal: parameter '" + name + "' not set");
}

bool ParamMap::GetBool(const std::string& name) const {
  if (auto* b = std::get_if<bool>(&Get(name))) return *b;
  throw Error("internal: parameter '" + name + "' is not a bool");
}

std::int64_t ParamMap::GetInt(const std::string& name) const {
  if (auto* i = std::get_if<std::int64_t>(&Get(name))) return *i;
  throw Error("internal: parameter '" + name + "' is not an int");
}

double ParamMap::GetDouble(const std::string& name) const {
  const auto& v = Get(name);
  if (auto* d = std::get_if<double>(&v)) return *d;
  if (auto* i = std::get_if<std::int64_t>(&v)) return static_cast<double>(*i);
  throw Error("internal: parameter '" + name + "' is not a number");
}

const std::string& ParamMap::GetString(const std::string& name) const {
  if (auto* s = std::get_if<std::string>(&Get(name))) return *s;
  throw Error("internal: parameter '" + name + "' is not a string");
}

const StageSpec& ParamMap::GetStage(const std::string& name) const {
  if (auto* s = std::get_if<std::shared_ptr<StageSpec>>(&Get(name))) return **s;
  throw Error("internal: parameter '" + name + "' is not a stage");
}

std::string FormatDouble(double d) {
  if (std::isinf(d)) return d > 0 ? "inf" : "-inf";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", d);
  return buf;
}

std::string FormatParamValue(const ParamValue& v) {
  return std::visit(
      [](const auto& x) -> std::string {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, bool>) return x ? "true" : "false";
        else if constexpr (std::is_same_v<T, std::int64_t>) return std::to_string(x);
        else if constexpr (std::is_same_v<T, double>) return FormatDouble(x);
        else if constexpr (std::is_same_v<T, std::string>) return x;
        else {
          std::string s = x->stage + "(";
          bool first = true;
          for (const auto& [k, val] : x->params.items()) {
            s += (first ? "" : ", ") + k + "=" + FormatParamValue(val);
            first = false;
          }
          return s + ")";
        }
      },
      v);
}

std::string ParamSpec::RangeText() const {
  switch (type) {
    case ParamType::kBool: return "true|false";
    case ParamType::kString: return "any text";
    case ParamType::kStage: return "a stage of role " + stage_role;
    case ParamType::kChoice: {
      std::string s;
      for (const auto& c : choices) s += (s.empty() ? "" : "|") + c;
      return s;
    }
    case ParamType::kInt:
    case ParamType::kDouble: {
      // An integer field's type limits (int32 or int64) read as no bound.
      const bool lo = std::isfinite(min) && min > -2147483648.0, hi = std::isfinite(max) && max < 2147483647.0;
      if (!lo && !hi) return "any";
      if (lo && hi)
        return std::string(min_open ? "(" : "[") + FormatDouble(min) + ", " + FormatDouble(max) + (max_open ? ")" : "]");
      if (lo) return (min_open ? "> " : ">= ") + FormatDouble(min);
      return (max_open ? "< " : "<= ") + FormatDouble(max);
    }
  }
  return "";
}

void ParamSpec::CheckValue(const ParamValue& v) const {
  auto fail = [&](const std::string& why) {
    throw OptionError(name + " = " + FormatParamValue(v) + ": " + why);
  };
  switch (type) {
    case ParamType::kBool:
      if (!std::holds_alternative<bool>(v)) fail("must be true or false");
      return;
    case ParamType::kInt: {
      auto* i = std::get_if<std::int64_t>(&v);
      if (!i) fail("must be an integer");
      if (!InBounds(static_cast<double>(*i))) fail("out of range " + RangeText());
      return;
    }
    case ParamType::kDouble: {
      double d;
      if (auto* p = std::get_if<double>(&v)) d = *p;
      else if (auto* i = std::get_if<std::int64_t>(&v)) d = static_cast<double>(*i);
      else { fail("must be a number"); return; }
      if (std::isnan(d)) fail("must not be NaN");
      if (!InBounds(d)) fail("out of range " + RangeText());
      return;
    }
    case ParamType::kString:
      if (!std::holds_alternative<std::string>(v)) fail("must be a string");
      return;
    case ParamType::kChoice: {
      auto* s = std::get_if<std::string>(&v);
      if (!s) fail("must be one of " + RangeText());
      for (const auto& c : choices)
        if (c == *s) return;
      fail("must be one of " + RangeText());
      return;
    }
    case ParamType::kStage:
      if (!std::holds_alternative<std::shared_ptr<StageSpec>>(v)) fail("must be a stage");
      return;
  }
}

ParamSchema& ParamSchema::Add(ParamSpec s) {
  if (Find(s.name)) throw Error("internal: parameter '" + s.name + "' declared twice");
  s.CheckValue(s.default_value);  // a default outside its own range is a bug
  specs_.push_back(std::move(s));
  return *this;
}

ParamSchema& ParamSchema::Bool(const std::string& name, bool def, const std::string& doc) {
  ParamSpec s;
  s.name = name, s.type = ParamType::kBool, s.default_value = def, s.doc = doc;
  return Add(std::move(s));
}

ParamSchema& ParamSchema::Int(const std::string& name, std::int64_t def, const std::string& doc,
                              std::int64_t min, std::int64_t max) {
  ParamSpec s;
  s.name = name, s.type = ParamType::kInt, s.default_value = def, s.doc = doc;
  s.min = static_cast<double>(min), s.max = static_cast<double>(max);
  return Add(std::move(s));
}

ParamSchema& ParamSchema::Double(const std::string& name, double def, const std::string& doc,
                                 double min, double max) {
  ParamSpec s;
  s.name = name, s.type = ParamType::kDouble, s.default_value = def, s.doc = doc;
  s.min = min, s.max = max;
  return Add(std::move(s));
}

ParamSchema& ParamSchema::String(const std::string& name, const std::string& def,
                                 const std::string& doc) {
  ParamSpec s;
  s.name = name, s.type = ParamType::kString, s.default_value = def, s.doc = doc;
  return Add(std::move(s));
}

ParamSchema& ParamSchema::Choice(const std::string& name, const std::string& def,
                                 std::vector<std::string> choices, const std::string& doc) {
  ParamSpec s;
  s.name = name, s.type = ParamType::kChoice, s.default_value = def, s.doc = doc;
  s.choices = std::move(choices);
  return Add(std::move(s));
}

ParamSchema& ParamSchema::Stage(const std::string& name, const std::string& role,
                                const std::string& def, const std::string& doc) {
  ParamSpec s;
  s.name = name, s.type = ParamType::kStage, s.doc = doc, s.stage_role = role;
  auto spec = std::make_shared<StageSpec>();
  spec->stage = def;
  s.default_value = spec;
  return Add(std::move(s));
}

ParamSchema& ParamSchema::Stage(const std::string& name, const std::string& role, const StageSpec& def,
                                const std::string& doc) {
  ParamSpec s;
  s.name = name, s.type = ParamType::kStage, s.doc = doc, s.stage_role = role;
  s.default_value = std::make_shared<StageSpec>(def);
  return Add(std::move(s));
}

const ParamSpec* ParamSchema::Find(const std::string& name) const {
  for (const auto& s : specs_)
    if (s.name == name) return &s;
  return nullptr;
}

void InheritNestedDefaults(const ParamSpec& spec, StageSpec* nested) {
  if (spec.type != ParamType::kStage) return;
  const auto* def = std::get_if<std::shared_ptr<StageSpec>>(&spec.default_value);
  if (!def || !*def || (*def)->stage != nested->stage) return;
  for (const auto& [k, v] : (*def)->params.items())
    if (!nested->params.Has(k)) nested->params.Set(k, v);
}

}  // namespace arcs
