// One name table per option enum: the text a user writes in YAML, on the
// command line or as a Python keyword, declared once beside the enum, e.g.
//
//   enum class PairChoice { kClosest, kFirst };
//   inline constexpr EnumName<PairChoice> kPairChoiceNames[] = {
//       {PairChoice::kClosest, "closest"}, {PairChoice::kFirst, "first"}};
//
// The parameter binder (registry/bind.h) reads the table to make the
// choice list, decode a value and print a default.
#pragma once

#include "framework/error.h"

#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace arcs {

template <class E>
struct EnumName {
  E value;
  const char* name;
};

// The name of `v` in `table`; throws Error if `v` has none (a table missing a value is a bug).
template <class E>
std::string EnumToName(std::span<const EnumName<E>> table, E v) {
  for (const auto& e : table)
    if (e.value == v) return e.name;
  throw Error("internal: enum value " + std::to_string(static_cast<long long>(v)) + " has no name");
}

// The same for a table declared as an array (deduces E and the size).
template <class E, std::size_t N>
std::string EnumToName(const EnumName<E> (&table)[N], E v) {
  return EnumToName(std::span<const EnumName<E>>(table), v);
}

// The value named `name`; throws OptionError listing the names if none matches.
template <class E>
E EnumFromName(std::span<const EnumName<E>> table, const std::string& name) {
  std::string names;
  for (const auto& e : table) {
    if (name == e.name) return e.value;
    if (!names.empty()) names += '|';
    names += e.name;
  }
  throw OptionError("'" + name + "': must be one of " + names);
}

template <class E>
std::vector<std::string> EnumNames(std::span<const EnumName<E>> table) {
  std::vector<std::string> out;
  for (const auto& e : table) out.emplace_back(e.name);
  return out;
}

}  // namespace arcs
