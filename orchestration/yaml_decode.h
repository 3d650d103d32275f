// Decoding YAML values with located errors: the helpers every part of the
// experiment loader (spec.cpp, items.cpp, table_spec.cpp) reads its fields
// with. Every failure is an ExperimentError "FILE:LINE: field: message", or
// "FILE (--set override): field: message" for a node a --set made.
#pragma once

#include "framework/error.h"

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <string>
#include <vector>

namespace arcs {

// Validation error located in an experiment file.
class ExperimentError : public Error {
 public:
  using Error::Error;
};

// "file:line" of a node ("file (--set override)" for one without a mark).
std::string MarkOf(const std::string& file, const YAML::Node& node);
// Throws ExperimentError "MarkOf(file, node): field: msg".
[[noreturn]] void Fail(const std::string& file, const YAML::Node& node, const std::string& field,
                       const std::string& msg);
// A mapping whose keys are all in `allowed`; an unknown key fails with the
// nearest valid one (DidYouMean) and the list of valid keys.
void CheckKeys(const std::string& file, const YAML::Node& node, const std::string& field,
               const std::vector<std::string>& allowed);

std::string GetString(const std::string& file, const YAML::Node& node, const std::string& field);
bool GetBool(const std::string& file, const YAML::Node& node, const std::string& field);
std::int64_t GetInt(const std::string& file, const YAML::Node& node, const std::string& field);
double GetDouble(const std::string& file, const YAML::Node& node, const std::string& field);  // finite, or ±inf
// A text value or a list of them.
std::vector<std::string> GetStringList(const std::string& file, const YAML::Node& node, const std::string& field);

// Whole-text number parsing ("+3" allowed; nothing after the number).
bool ParseInt64(const std::string& s, std::int64_t* out);
bool ParseDouble(const std::string& s, double* out);  // also inf/.inf forms; NaN refused

}  // namespace arcs
