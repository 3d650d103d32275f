// Name -> stage registry. Registration is explicit (RegisterBuiltinStages and
// plugins' entry points); no static-initialisation tricks.
#pragma once

#include "registry/stage.h"

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

  // Resolves a stage's parameters: defaults, then `given` (already type-
  // checked values), nested stages resolved recursively. Throws OptionError.
  ParamMap Resolve(const std::string& stage, const ParamMap& given) const;

 private:
  std::vector<StageInfo> stages_;
};

// Registers a stage made from a plain function (the common thin adaptor):
// fills StageInfo and calls r.Register (which refuses duplicate names).
void RegisterFunctionStage(Registry& r, const std::string& name, Role role, const std::string& doc,
                           ParamSchema params, std::vector<std::string> outputs, StageFn fn);

}  // namespace arcs
