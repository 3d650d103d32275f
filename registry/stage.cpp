#include "registry/stage.h"

#include "registry/registry.h"

namespace arcs {

namespace {
struct RoleEntry {
  Role role;
  const char* name;
};
constexpr RoleEntry kRoles[] = {
    {Role::kSdfSampler, "sdf_sampler"},
    {Role::kSdfModifier, "sdf_modifier"},
    {Role::kSdfToMesh, "sdf_to_mesh"},
    {Role::kEmptySpaceSampler, "empty_space_sampler"},
    {Role::kArcProjector, "arc_projector"},
    {Role::kFineTuner, "fine_tuner"},
    {Role::kReconstructor, "reconstructor"},
    {Role::kVoxelizer, "voxelizer"},
    {Role::kPointSampler, "point_sampler"},
    {Role::kPointModifier, "point_modifier"},
    {Role::kEvaluator, "evaluator"},
    {Role::kOther, "other"},
};
}  // namespace

const char* RoleName(Role r) {
  for (const auto& e : kRoles)
    if (e.role == r) return e.name;
  return "other";
}

Role ParseRole(const std::string& name) {
  for (const auto& e : kRoles)
    if (name == e.name) return e.role;
  throw Error("unknown role '" + name + "'");
}

void CaseData::SetMetric(const std::string& name, double v) {
  for (auto& [k, val] : metrics) {
    if (k == name) {
      val = v;
      return;
    }
  }
  metrics.emplace_back(name, v);
}

const Mesh& CaseData::RequireReference(const std::string& stage) const {
  if (!reference) throw Error(stage + ": needs a reference mesh (the dataset item), but this case has none");
  return *reference;
}

const SdfSamples& CaseData::RequireSamples(const std::string& stage) const {
  if (!samples) throw Error(stage + ": needs SDF samples; put an sdf sampler before it or load samples");
  return *samples;
}

const Mesh& CaseData::RequireOutput(const std::string& stage) const {
  if (!output) throw Error(stage + ": needs the method's output mesh, but the method produced none");
  return *output;
}

void RunNestedStage(const StageSpec& spec, Context& ctx, CaseData& data) {
  if (!data.registry) throw Error("internal: nested stage '" + spec.stage + "' needs the case's registry");
  auto stage = data.registry->Get(spec.stage).factory(spec.params);
  stage->Run(ctx, data);
}

namespace {
class FnStage : public Stage {
 public:
  FnStage(StageFn fn, ParamMap p) : fn_(std::move(fn)), params_(std::move(p)) {}
  void Run(Context& ctx, CaseData& data) override { fn_(ctx, data, params_); }

 private:
  StageFn fn_;
  ParamMap params_;
};
}  // namespace

StageFactory FunctionStage(StageFn fn) {
  return [fn = std::move(fn)](const ParamMap& p) -> std::unique_ptr<Stage> {
    return std::make_unique<FnStage>(fn, p);
  };
}

}  // namespace arcs
