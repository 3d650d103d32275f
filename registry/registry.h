// Name -> stage registry. Registration is explicit (RegisterBuiltinStages and
// plugins' entry points); no static-initialisation tricks.
#pragma once

#include "registry/stage.h"

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace arcs {

class Registry {
 public:
  // Adds a stage. Throws Error naming both origins if the name is taken.
  void Register(StageInfo info);

  const StageInfo* Find(const std::string& name) const;
  // Like Find, but throws Error "unknown stage 'x' (did you mean 'y'?)".
  const StageInfo& Get(const std::string& name) const;
  // All stages, sorted by role then name.
  std::vector<const StageInfo*> List() const;
  // The registered name closest to `name` (NearestName, framework/util/suggest.h),
  // or "" if none is close.
  std::string Suggest(const std::string& name) const;

  // A stage object for a resolved spec (the same as Get(name).factory(params):
  // every factory registered here attaches the stage's declaration, so
  // Stage::Run checks its contract). Throws Error if the stage is unknown.
  std::unique_ptr<Stage> Create(const StageSpec& spec) const;

  // Checks a pipeline's data flow before anything runs: each stage must find
  // the slots it reads among `start` (what the dataset item gives) and what
  // the stages before it write, and must work in dimension `dim` (2 or 3;
  // 0 = not known yet). The check stops at a stage that declares no flow.
  // Throws Error "WHERE: stage 'x' needs free_points, which ..." where WHERE
  // is where(i) for the i-th stage (e.g. "exp.yaml:12"; empty: no prefix).
  void CheckPipeline(const std::vector<std::string>& stages, Slots start, int dim,
                     const std::function<std::string(std::size_t)>& where = {}) const;

  // The stages that write any of `slots` and work in `dim` (0: any), as
  // "a, b, c" (sorted by role, then name).
  std::string WritersOf(Slots slots, int dim) const;

  // Resolves a stage's parameters: defaults, then `given` (already type-
  // checked values), nested stages resolved recursively, then the
  // algorithm's own check (StageInfo::check). Throws OptionError
  // "stage.param = value: ...".
  ParamMap Resolve(const std::string& stage, const ParamMap& given) const;

 private:
  std::vector<StageInfo> stages_;
};

// Registers a stage made from a plain function (the common thin adaptor):
// fills StageInfo and calls r.Register (which refuses duplicate names).
void RegisterFunctionStage(Registry& r, const std::string& name, Role role, const std::string& doc,
                           ParamSchema params, std::vector<std::string> outputs, StageFn fn);

}  // namespace arcs
