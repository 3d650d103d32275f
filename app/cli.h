// Command-line helpers shared by the `arcs` subcommands (app/*.cpp).
#pragma once

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

namespace arcs::cli {

[[noreturn]] inline void Usage(const std::string& msg) {
  std::fprintf(stderr, "arcs: %s\n(run `arcs --help` for usage)\n", msg.c_str());
  std::exit(2);
}

struct Args {
  std::vector<std::string> positional;
  std::vector<std::pair<std::string, std::string>> options;  // --key value (value "" for flags)
  bool Has(const std::string& k) const {
    for (const auto& [a, b] : options)
      if (a == k) return true;
    return false;
  }
  std::string Get(const std::string& k, const std::string& def = "") const {
    for (const auto& [a, b] : options)
      if (a == k) return b;
    return def;
  }
  std::vector<std::string> All(const std::string& k) const {
    std::vector<std::string> out;
    for (const auto& [a, b] : options)
      if (a == k) out.push_back(b);
    return out;
  }
};

inline Args Parse(int argc, char** argv, int start, const std::vector<std::string>& with_value,
           const std::vector<std::string>& flags) {
  Args a;
  for (int i = start; i < argc; ++i) {
    std::string s = argv[i];
    if (s.rfind("--", 0) == 0) {
      std::string key = s, val;
      const size_t eq = s.find('=');
      if (eq != std::string::npos && std::find(with_value.begin(), with_value.end(), s.substr(0, eq)) != with_value.end()) {
        key = s.substr(0, eq);
        val = s.substr(eq + 1);
      } else if (std::find(with_value.begin(), with_value.end(), key) != with_value.end()) {
        if (i + 1 >= argc) Usage("option " + key + " needs a value");
        val = argv[++i];
      } else if (std::find(flags.begin(), flags.end(), key) == flags.end()) {
        Usage("unknown option " + key);
      }
      a.options.emplace_back(key, val);
    } else {
      a.positional.push_back(s);
    }
  }
  return a;
}

// An integer option in [lo, hi]: no wrap-around (4294967302 is out of the
// int range, not 6), no trailing junk, no empty value.
inline long long ParseInt64(const std::string& s, const std::string& what, long long lo = LLONG_MIN,
                            long long hi = LLONG_MAX) {
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(s.c_str(), &end, 10);
  if (s.empty() || *end || std::isspace(static_cast<unsigned char>(s[0])))
    Usage(what + " must be an integer, got '" + s + "'");
  if (errno == ERANGE || v < lo || v > hi)
    Usage(what + " = " + s + " is out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return v;
}

inline int ParseInt(const std::string& s, const std::string& what, int lo = INT_MIN, int hi = INT_MAX) {
  return static_cast<int>(ParseInt64(s, what, lo, hi));
}

inline double ParseDouble(const std::string& s, const std::string& what) {
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || *end) Usage(what + " must be a number, got '" + s + "'");
  if (!std::isfinite(v)) Usage(what + " must be a finite number, got '" + s + "'");
  return v;
}

}  // namespace arcs::cli

// Command-line flags made from a stage's parameter schema (registry/bind.h:
// one declaration per parameter), so a command such as `arcs voxelize` or
// `arcs morph` takes a stage's parameters with the stage's names, docs,
// defaults, bounds and the algorithm's own Check(), all from one place.
#include "registry/registry.h"

#include <cstdint>

namespace arcs::cli {

// One flag: "--open-mesh" for the parameter "open_mesh".
struct SchemaFlag {
  std::string flag;
  ParamSpec spec;
};

// The flags of `stage`'s int, double, choice and string parameters in schema
// order: "--" + the name with '_' written '-', or the name `renames` gives
// (parameter -> flag without "--"); parameters in `skip` get none.
inline std::vector<SchemaFlag> StageFlags(const Registry& registry, const std::string& stage,
                                          const std::vector<std::string>& skip = {},
                                          const std::vector<std::pair<std::string, std::string>>& renames = {}) {
  std::vector<SchemaFlag> out;
  for (const ParamSpec& s : registry.Get(stage).params.specs()) {
    if (s.type != ParamType::kInt && s.type != ParamType::kDouble && s.type != ParamType::kChoice &&
        s.type != ParamType::kString)
      continue;
    if (std::find(skip.begin(), skip.end(), s.name) != skip.end()) continue;
    std::string f = s.name;
    std::replace(f.begin(), f.end(), '_', '-');
    for (const auto& [param, flag] : renames)
      if (param == s.name) f = flag;
    out.push_back({"--" + f, s});
  }
  return out;
}

// The flag names, for Parse's list of options that take a value.
inline std::vector<std::string> FlagNames(const std::vector<SchemaFlag>& flags) {
  std::vector<std::string> out;
  for (const auto& f : flags) out.push_back(f.flag);
  return out;
}

// Help lines: "  --flag V              doc (default D; RANGE)".
inline std::string FlagHelp(const std::vector<SchemaFlag>& flags) {
  std::string out;
  for (const auto& f : flags) {
    std::string head = "  " + f.flag + (f.spec.type == ParamType::kChoice ? " C" : f.spec.type == ParamType::kInt ? " N" : " X");
    if (head.size() < 24) head.resize(24, ' ');
    else head += ' ';
    out += head + f.spec.doc + " (default " + FormatParamValue(f.spec.default_value) + "; " + f.spec.RangeText() + ")\n";
  }
  return out;
}

// The stage's parameters resolved from the flags present in `a` (the rest at
// their defaults), through Registry::Resolve: the schema's bounds and the
// algorithm's Check() apply. A bad value is a usage error (exit 2) naming
// the flag and the stage's parameter.
inline ParamMap ResolveStageFlags(const Registry& registry, const std::string& stage,
                                  const std::vector<SchemaFlag>& flags, const Args& a) {
  ParamMap given;
  for (const auto& f : flags) {
    if (!a.Has(f.flag)) continue;
    const std::string text = a.Get(f.flag);
    if (f.spec.type == ParamType::kInt)
      given.Set(f.spec.name, static_cast<std::int64_t>(ParseInt64(text, f.flag)));
    else if (f.spec.type == ParamType::kDouble)
      given.Set(f.spec.name, ParseDouble(text, f.flag));
    else
      given.Set(f.spec.name, text);
  }
  try {
    return registry.Resolve(stage, given);
  } catch (const OptionError& e) {
    std::string flag;
    const std::string what = e.what();
    for (const auto& f : flags)
      if (what.rfind(stage + "." + f.spec.name + " ", 0) == 0) flag = f.flag;
    Usage(what + (flag.empty() ? "" : " (option " + flag + ")"));
  }
}

}  // namespace arcs::cli
