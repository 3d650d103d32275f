// One declaration per parameter: a Binder ties a parameter's name, doc and
// bounds to a field of an algorithm's Options struct. From that single line
// come the stage schema (YAML decoding, `arcs describe`, `--set`, the CLI
// flags of `voxelize`/`morph`, the Python keywords), the default (read from
// the Options object, `Options{}` unless a stage starts from a preset), the
// decoding of resolved values into the struct, and the algorithm's own
// Check() run at load time on the decoded struct.
//
//   const Binder<ArcProjectorOptions>& ArcProjectorParams() {
//     static const auto b = Binder<ArcProjectorOptions>()
//         .Int("local_search_iters", &ArcProjectorOptions::local_search_iters, "make-feasible steps",
//              Closed(0, 10000))
//         .Double("tol", &ArcProjectorOptions::tol, "containment tolerance", HalfOpen(0, 0.1))
//         .Enum("pair_choice", &ArcProjectorOptions::pair_choice, kPairChoiceNames, "candidate rule");
//     return b;
//   }
//
// The test tests/registry/bounds_agree_test.cpp walks every bound stage and
// checks that its declared bounds and the algorithm's Check() agree at both
// ends of every numeric parameter.
#pragma once

#include "framework/util/enum_names.h"
#include "registry/param.h"
#include "registry/stage.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace arcs {

// Bounds of a numeric parameter; ends are closed unless marked open.
struct Bounds {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_open = false;
  bool max_open = false;
};
inline constexpr Bounds Closed(double lo, double hi) { return {lo, hi, false, false}; }    // [lo, hi]
inline constexpr Bounds HalfOpen(double lo, double hi) { return {lo, hi, false, true}; }   // [lo, hi)
inline constexpr Bounds LeftOpen(double lo, double hi) { return {lo, hi, true, false}; }   // (lo, hi]
inline constexpr Bounds Open(double lo, double hi) { return {lo, hi, true, true}; }        // (lo, hi)
inline constexpr Bounds AtLeast(double lo) { return {lo, std::numeric_limits<double>::infinity(), false, false}; }
inline constexpr Bounds Above(double lo) { return {lo, std::numeric_limits<double>::infinity(), true, false}; }

template <class O>
class Binder {
 public:
  using CheckFn = std::function<void(const O&)>;

  // Defaults are read from `defaults` (normally O{}). Check() of O, if it
  // has one, is the algorithm's validity check.
  explicit Binder(O defaults = O{}) : defaults_(std::make_shared<O>(std::move(defaults))) {
    if constexpr (requires(const O& o) { o.Check(); }) check_ = [](const O& o) { o.Check(); };
  }

  // An integer field (int, int64_t, ...). Open-ended bounds stop at the
  // field type's range, so an `int` field never takes 2^40.
  template <class T>
  Binder& Int(const std::string& name, T O::*field, const std::string& doc, Bounds b = {}) {
    static_assert(std::is_integral_v<T> && !std::is_same_v<T, bool>, "Int binds an integer field");
    constexpr double lo = static_cast<double>(std::numeric_limits<T>::min());
    constexpr double hi = static_cast<double>(std::numeric_limits<T>::max());
    if (b.min < lo) b.min = lo, b.min_open = false;
    if (b.max > hi) b.max = hi, b.max_open = false;
    ParamSpec s = Spec(name, ParamType::kInt, doc, b);
    s.default_value = static_cast<std::int64_t>((*defaults_).*field);
    return Add(std::move(s),
               [field](O& o, const ParamValue& v) { o.*field = static_cast<T>(std::get<std::int64_t>(v)); },
               [field](const O& o) { return ParamValue(static_cast<std::int64_t>(o.*field)); });
  }

  Binder& Double(const std::string& name, double O::*field, const std::string& doc, Bounds b = {}) {
    ParamSpec s = Spec(name, ParamType::kDouble, doc, b);
    s.default_value = (*defaults_).*field;
    return Add(std::move(s), [field](O& o, const ParamValue& v) { o.*field = AsDouble(v); },
               [field](const O& o) { return ParamValue(o.*field); });
  }

  Binder& Bool(const std::string& name, bool O::*field, const std::string& doc) {
    ParamSpec s = Spec(name, ParamType::kBool, doc, {});
    s.default_value = (*defaults_).*field;
    return Add(std::move(s), [field](O& o, const ParamValue& v) { o.*field = std::get<bool>(v); },
               [field](const O& o) { return ParamValue(o.*field); });
  }

  Binder& String(const std::string& name, std::string O::*field, const std::string& doc) {
    ParamSpec s = Spec(name, ParamType::kString, doc, {});
    s.default_value = (*defaults_).*field;
    return Add(std::move(s), [field](O& o, const ParamValue& v) { o.*field = std::get<std::string>(v); },
               [field](const O& o) { return ParamValue(o.*field); });
  }

  // An enum field with its one name table (framework/util/enum_names.h).
  template <class E, std::size_t N>
  Binder& Enum(const std::string& name, E O::*field, const EnumName<E> (&table)[N], const std::string& doc) {
    const std::span<const EnumName<E>> t(table, N);
    ParamSpec s = Spec(name, ParamType::kChoice, doc, {});
    s.choices = EnumNames(t);
    s.default_value = EnumToName(t, (*defaults_).*field);
    return Add(std::move(s),
               [field, t](O& o, const ParamValue& v) { o.*field = EnumFromName(t, std::get<std::string>(v)); },
               [field, t](const O& o) { return ParamValue(EnumToName(t, o.*field)); });
  }

  // A choice bound to a std::string field (an Options struct that keeps its
  // choices as text, e.g. VoxelizeOptions::method); the default is the field's.
  Binder& Choice(const std::string& name, std::string O::*field, std::vector<std::string> choices,
                 const std::string& doc) {
    ParamSpec s = Spec(name, ParamType::kChoice, doc, {});
    s.choices = std::move(choices);
    s.default_value = (*defaults_).*field;
    return Add(std::move(s), [field](O& o, const ParamValue& v) { o.*field = std::get<std::string>(v); },
               [field](const O& o) { return ParamValue(o.*field); });
  }

  // A nested option group: every parameter of `group` (or those named in
  // `only`, in the group's order) is a parameter of this stage, bound to the
  // same field of the member `field` (e.g. the make-feasible settings that
  // projector and fine-tuner share).
  template <class G>
  Binder& Group(G O::*field, const Binder<G>& group, std::vector<std::string> only = {}) {
    for (const auto& gb : group.bindings()) {
      if (!only.empty() && std::find(only.begin(), only.end(), gb.spec.name) == only.end()) continue;
      ParamSpec s = gb.spec;
      if (gb.get) s.default_value = gb.get((*defaults_).*field);  // this struct's defaults win
      auto set = gb.set;
      auto get = gb.get;
      if (set)
        Add(std::move(s), [field, set](O& o, const ParamValue& v) { set(o.*field, v); },
            [field, get](const O& o) { return get(o.*field); });
      else
        Add(std::move(s), nullptr, nullptr);
    }
    return *this;
  }

  // A parameter the stage itself reads (a nested stage, a stage-level
  // choice): in the schema, not in O.
  Binder& Unbound(ParamSpec s) { return Add(std::move(s), nullptr, nullptr); }
  Binder& Stage(const std::string& name, const std::string& role, const std::string& def, const std::string& doc) {
    ParamSchema tmp;
    tmp.Stage(name, role, def, doc);
    return Unbound(tmp.specs().front());
  }
  Binder& Stage(const std::string& name, const std::string& role, const StageSpec& def, const std::string& doc) {
    ParamSchema tmp;
    tmp.Stage(name, role, def, doc);
    return Unbound(tmp.specs().front());
  }
  Binder& Choice(const std::string& name, const std::string& def, std::vector<std::string> choices,
                 const std::string& doc) {
    ParamSchema tmp;
    tmp.Choice(name, def, std::move(choices), doc);
    return Unbound(tmp.specs().front());
  }

  // Replaces the validity check (default: O::Check()).
  Binder& Check(CheckFn fn) {
    check_ = std::move(fn);
    return *this;
  }

  // The schema, in declaration order, defaults from the defaults object.
  ParamSchema Schema() const {
    ParamSchema s;
    for (const auto& b : bindings_) s.Add(b.spec);
    return s;
  }

  // The defaults object with every bound parameter present in `p` decoded
  // into it (resolved values: types already checked). No validity check.
  O Decode(const ParamMap& p) const {
    O o = *defaults_;
    for (const auto& b : bindings_)
      if (b.set && p.Has(b.spec.name)) b.set(o, p.Get(b.spec.name));
    return o;
  }

  // The algorithm's check on a decoded struct (no-op without one).
  void CheckOptions(const O& o) const {
    if (check_) check_(o);
  }

  // The bound parameters of `o` as values (e.g. to forward options from one
  // stage to a nested one).
  ParamMap Encode(const O& o) const {
    ParamMap m;
    for (const auto& b : bindings_)
      if (b.get) m.Set(b.spec.name, b.get(o));
    return m;
  }

  struct Binding {
    ParamSpec spec;
    std::function<void(O&, const ParamValue&)> set;  // null: not a field of O
    std::function<ParamValue(const O&)> get;
  };
  const std::vector<Binding>& bindings() const { return bindings_; }

 private:
  static double AsDouble(const ParamValue& v) {
    if (const auto* i = std::get_if<std::int64_t>(&v)) return static_cast<double>(*i);
    return std::get<double>(v);
  }
  static ParamSpec Spec(const std::string& name, ParamType type, const std::string& doc, const Bounds& b) {
    ParamSpec s;
    s.name = name, s.type = type, s.doc = doc;
    s.min = b.min, s.max = b.max, s.min_open = b.min_open, s.max_open = b.max_open;
    return s;
  }
  Binder& Add(ParamSpec s, std::function<void(O&, const ParamValue&)> set, std::function<ParamValue(const O&)> get) {
    for (const auto& b : bindings_)
      if (b.spec.name == s.name) throw Error("internal: parameter '" + s.name + "' bound twice");
    s.CheckValue(s.default_value);  // a default outside its own bounds is a bug
    bindings_.push_back({std::move(s), std::move(set), std::move(get)});
    return *this;
  }

  std::shared_ptr<const O> defaults_;
  std::vector<Binding> bindings_;
  CheckFn check_;
};

// A stage body with its parameters decoded: `o` is the options struct, `p`
// the resolved map (for the stage's unbound parameters, e.g. nested stages).
template <class O>
using BoundStageFn = std::function<void(Context& ctx, CaseData& d, const O& o, const ParamMap& p)>;

// Makes `info` a stage of `binder`'s parameters: its schema, its load-time
// check (decode + the algorithm's Check()) and a factory that decodes the
// resolved parameters and calls `run`.
template <class O>
void BindStage(StageInfo& info, const Binder<O>& binder, BoundStageFn<O> run) {
  info.params = binder.Schema();
  auto b = std::make_shared<const Binder<O>>(binder);
  info.check = [b](const ParamMap& p) { b->CheckOptions(b->Decode(p)); };
  info.factory = FunctionStage(
      [b, run = std::move(run)](Context& ctx, CaseData& d, const ParamMap& p) { run(ctx, d, b->Decode(p), p); });
}

}  // namespace arcs
