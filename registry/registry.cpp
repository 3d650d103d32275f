#include "registry/registry.h"

#include "framework/util/suggest.h"

#include <algorithm>

namespace arcs {

void Registry::Register(StageInfo info) {
  if (info.name.empty()) throw Error("a stage from " + info.origin + " has an empty name");
  if (!info.factory) throw Error("stage '" + info.name + "' from " + info.origin + " has no factory");
  if (const StageInfo* old = Find(info.name)) {
    throw Error("stage '" + info.name + "' registered twice: by " + old->origin + " and by " +
                info.origin);
  }
  // Every stage the factory makes carries its declaration, so Stage::Run
  // checks the contract however the stage was made. The copy it points to
  // lives as long as any copy of the factory (registries may be copied).
  auto contract = std::make_shared<StageInfo>(info);
  contract->factory = nullptr;
  info.factory = [inner = std::move(info.factory), contract](const ParamMap& p) {
    std::unique_ptr<Stage> s = inner(p);
    if (!s) throw Error("stage '" + contract->name + "': its factory made no stage");
    s->set_info(contract.get());
    return s;
  };
  stages_.push_back(std::move(info));
}

const StageInfo* Registry::Find(const std::string& name) const {
  for (const auto& s : stages_)
    if (s.name == name) return &s;
  return nullptr;
}

const StageInfo& Registry::Get(const std::string& name) const {
  if (const StageInfo* s = Find(name)) return *s;
  std::string msg = "unknown stage '" + name + "'";
  const std::string near = Suggest(name);
  if (!near.empty()) msg += " (did you mean '" + near + "'?)";
  msg += "; `arcs list` shows all stages";
  throw Error(msg);
}

std::vector<const StageInfo*> Registry::List() const {
  std::vector<const StageInfo*> out;
  for (const auto& s : stages_) out.push_back(&s);
  std::sort(out.begin(), out.end(), [](const StageInfo* a, const StageInfo* b) {
    if (a->role != b->role) return a->role < b->role;
    return a->name < b->name;
  });
  return out;
}

std::string Registry::Suggest(const std::string& name) const {
  std::vector<std::string> names;
  for (const auto& s : stages_) names.push_back(s.name);
  return NearestName(name, names);
}

ParamMap Registry::Resolve(const std::string& stage, const ParamMap& given) const {
  const StageInfo& info = Get(stage);
  for (const auto& [k, v] : given.items()) {
    if (!info.params.Find(k)) {
      std::string msg = "stage '" + stage + "' has no parameter '" + k + "'";
      std::string valid;
      for (const auto& s : info.params.specs()) valid += (valid.empty() ? "" : ", ") + s.name;
      msg += valid.empty() ? " (it takes none)" : " (valid: " + valid + ")";
      throw OptionError(msg);
    }
  }
  ParamMap out;
  for (const auto& spec : info.params.specs()) {
    ParamValue v = given.Has(spec.name) ? given.Get(spec.name) : spec.default_value;
    // Integers are accepted where floats are expected.
    if (spec.type == ParamType::kDouble)
      if (auto* i = std::get_if<std::int64_t>(&v)) v = static_cast<double>(*i);
    try {
      spec.CheckValue(v);
    } catch (const OptionError& e) {
      throw OptionError(stage + "." + e.what());
    }
    if (spec.type == ParamType::kStage) {
      const auto& nested = *std::get<std::shared_ptr<StageSpec>>(v);
      const StageInfo& ninfo = Get(nested.stage);
      if (RoleName(ninfo.role) != spec.stage_role)
        throw OptionError(stage + "." + spec.name + " = " + nested.stage + ": must be a stage of role " +
                          spec.stage_role + ", but '" + nested.stage + "' is a " + RoleName(ninfo.role));
      StageSpec base = nested;  // the default itself when not given: inheriting adds nothing
      InheritNestedDefaults(spec, &base);
      auto resolved = std::make_shared<StageSpec>();
      resolved->stage = nested.stage;
      resolved->params = Resolve(nested.stage, base.params);
      v = resolved;
    }
    out.Set(spec.name, std::move(v));
  }
  if (info.check) {
    try {
      info.check(out);
    } catch (const Cancelled&) {
      throw;
    } catch (const std::exception& e) {
      const std::string what = e.what();
      throw OptionError(NamesStage(what, stage) ? what : stage + "." + what);
    }
  }
  return out;
}

std::string Registry::WritersOf(Slots slots, int dim) const {
  std::string out;
  for (const StageInfo* w : List()) {
    if (!w->declared) continue;
    bool writes_one = false;
    for (Slot s : kAllSlots) writes_one |= slots.Has(s) && w->writes.Has(s);
    if (writes_one && WorksIn(w->dims, dim)) out += (out.empty() ? "" : ", ") + w->name;
  }
  return out;
}

std::unique_ptr<Stage> Registry::Create(const StageSpec& spec) const { return Get(spec.stage).factory(spec.params); }

void Registry::CheckPipeline(const std::vector<std::string>& stages, Slots start, int dim,
                             const std::function<std::string(std::size_t)>& where) const {
  Slots have = start;
  for (std::size_t i = 0; i < stages.size(); ++i) {
    const StageInfo& info = Get(stages[i]);
    if (!info.declared) return;  // says nothing of its flow: nothing after it can be checked
    auto fail = [&](const std::string& what) {
      const std::string w = where ? where(i) : "";
      throw Error((w.empty() ? "" : w + ": ") + "stage '" + info.name + "' " + what);
    };
    const Slots missing = info.reads.Without(have);
    if (!missing.Empty()) {
      const std::string writers = WritersOf(missing, dim);
      fail("needs " + missing.Text() + ", which " +
           (i == 0 ? std::string("the dataset item does not give") : "neither the dataset item nor the stages before it give") +
           " (the case has " + have.Text() + " there)" +
           (writers.empty() ? "" : "; put one of these before it: " + writers));
    }
    if (!WorksIn(info.dims, dim))
      fail("works on " + DimsText(info.dims) + " data, but this pipeline is " + std::to_string(dim) + "D");
    have = have | info.writes;
  }
}

void RegisterFunctionStage(Registry& r, const std::string& name, Role role, const std::string& doc,
                           ParamSchema params, std::vector<std::string> outputs, StageFn fn) {
  StageInfo s;
  s.name = name;
  s.role = role;
  s.doc = doc;
  s.params = std::move(params);
  s.outputs = std::move(outputs);
  s.factory = FunctionStage(std::move(fn));
  r.Register(std::move(s));
}

}  // namespace arcs
