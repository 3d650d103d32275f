// Parameter schemas and values.
//
// One schema per stage drives YAML decoding (strict: unknown keys, wrong
// types and out-of-range values are errors), `arcs describe`, and the
// `--set stage.param=value` overrides.
#pragma once

#include "framework/error.h"

#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <variant>
#include <vector>

namespace arcs {

struct StageSpec;

enum class ParamType { kBool, kInt, kDouble, kString, kChoice, kStage };
const char* ParamTypeName(ParamType t);

// A resolved parameter value. kStage parameters hold a nested stage with its
// own resolved parameters (e.g. the fine-tuner's reconstructor).
using ParamValue = std::variant<bool, std::int64_t, double, std::string, std::shared_ptr<StageSpec>>;

// Resolved parameters of one stage, in schema order.
class ParamMap {
 public:
  void Set(const std::string& name, ParamValue v);
  bool Has(const std::string& name) const;
  const ParamValue& Get(const std::string& name) const;  // throws Error if missing

  bool GetBool(const std::string& name) const;
  std::int64_t GetInt(const std::string& name) const;
  double GetDouble(const std::string& name) const;  // ints convert
  const std::string& GetString(const std::string& name) const;  // string and choice
  const StageSpec& GetStage(const std::string& name) const;

  const std::vector<std::pair<std::string, ParamValue>>& items() const { return items_; }

 private:
  std::vector<std::pair<std::string, ParamValue>> items_;
};

// A stage name with its resolved parameters.
struct StageSpec {
  std::string stage;
  ParamMap params;
};

// Canonical text of a value (used in CSV cells, case ids, describe output).
std::string FormatParamValue(const ParamValue& v);

struct ParamSpec {
  std::string name;
  ParamType type = ParamType::kDouble;
  ParamValue default_value;
  double min = -std::numeric_limits<double>::infinity();  // bounds for numbers
  double max = std::numeric_limits<double>::infinity();
  bool min_open = false;  // true: min itself is refused, "(min, ..."
  bool max_open = false;  // true: max itself is refused, "..., max)"
  std::vector<std::string> choices;  // kChoice
  std::string stage_role;            // kStage: the role the nested stage must have
  std::string doc;                   // one line

  // "[1, 2048]", "[0, 0.1)", "> 0", "a|b", "any", ... for messages and describe output.
  std::string RangeText() const;
  // Throws OptionError naming the parameter if v is not allowed.
  void CheckValue(const ParamValue& v) const;
  // Whether a number lies within [min, max] (ends open where marked).
  bool InBounds(double v) const {
    return (min_open ? v > min : v >= min) && (max_open ? v < max : v <= max);
  }
};

// A nested stage given for a stage parameter whose default names the same
// stage starts from the default's parameters, the given ones on top: in
// rfta, `reconstructor: {stage: screened_poisson, params: {point_weight: 4}}`
// (or `reconstructor: screened_poisson`) is the default call (the official
// one) with weight 4, not screened_poisson's own defaults. Another stage
// starts from its own defaults. Keys already given are kept.
void InheritNestedDefaults(const ParamSpec& spec, StageSpec* nested);

// Fluent builder of a stage's parameter list.
class ParamSchema {
 public:
  ParamSchema& Bool(const std::string& name, bool def, const std::string& doc);
  ParamSchema& Int(const std::string& name, std::int64_t def, const std::string& doc,
                   std::int64_t min = std::numeric_limits<std::int64_t>::min(),
                   std::int64_t max = std::numeric_limits<std::int64_t>::max());
  ParamSchema& Double(const std::string& name, double def, const std::string& doc,
                      double min = -std::numeric_limits<double>::infinity(),
                      double max = std::numeric_limits<double>::infinity());
  ParamSchema& String(const std::string& name, const std::string& def, const std::string& doc);
  ParamSchema& Choice(const std::string& name, const std::string& def,
                      std::vector<std::string> choices, const std::string& doc);
  // A nested stage of the given role; `def` names the default stage (its
  // parameters take their own defaults).
  ParamSchema& Stage(const std::string& name, const std::string& role, const std::string& def,
                     const std::string& doc);
  // The same with parameters for the default stage (the rest take their defaults).
  ParamSchema& Stage(const std::string& name, const std::string& role, const StageSpec& def,
                     const std::string& doc);

  // Adds a fully described parameter (the binder's way in, registry/bind.h).
  // Throws Error if the name is taken or the default is outside its range.
  ParamSchema& Add(ParamSpec s);

  const std::vector<ParamSpec>& specs() const { return specs_; }
  const ParamSpec* Find(const std::string& name) const;

 private:
  std::vector<ParamSpec> specs_;
};

}  // namespace arcs
