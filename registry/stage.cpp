#include "registry/stage.h"

#include "registry/registry.h"

#include <chrono>

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

const char* SlotName(Slot s) {
  switch (s) {
    case Slot::kReference: return "reference";
    case Slot::kSamples: return "samples";
    case Slot::kFreePoints: return "free_points";
    case Slot::kPoints: return "points";
    case Slot::kOutput: return "output";
    case Slot::kVolume: return "volume";
  }
  return "?";
}

std::string Slots::Text() const {
  std::string out;
  for (Slot s : kAllSlots)
    if (Has(s)) out += (out.empty() ? "" : ", ") + std::string(SlotName(s));
  return out.empty() ? "nothing" : out;
}

bool NamesStage(const std::string& what, const std::string& stage) {
  return what.size() > stage.size() && what.compare(0, stage.size(), stage) == 0 &&
         (what[stage.size()] == ':' || what[stage.size()] == '.');
}

std::string DimsText(unsigned dims) {
  if ((dims & kAnyDim) == kAnyDim) return "2D and 3D";
  if (dims & k2D) return "2D";
  if (dims & k3D) return "3D";
  return "no dimension";
}

Slots CaseData::Present() const {
  Slots s;
  if (reference || reference_curve) s = s | Slots{Slot::kReference};
  if (samples) s = s | Slots{Slot::kSamples};
  if (free_points) s = s | Slots{Slot::kFreePoints};
  if (points) s = s | Slots{Slot::kPoints};
  if (output || output_curve) s = s | Slots{Slot::kOutput};
  if (volume) s = s | Slots{Slot::kVolume};
  return s;
}

int CaseData::Dim() const {
  if (samples) return samples->dim;
  if (reference_curve || output_curve) return 2;
  if (reference || output || volume) return 3;
  return 0;
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

namespace {
// "NAME: what", unless `what` already names the stage.
std::string Prefixed(const std::string& name, const std::string& what) {
  return NamesStage(what, name) ? what : name + ": " + what;
}
}  // namespace

void Stage::Run(Context& ctx, CaseData& data) {
  ctx.CheckStop();
  if (!info_) {
    Execute(ctx, data);
    return;
  }
  const std::string& name = info_->name;
  const Slots missing = info_->reads.Without(data.Present());
  if (!missing.Empty()) {
    const std::string writers = data.registry ? data.registry->WritersOf(missing, data.Dim()) : "";
    throw Error(name + ": needs " + missing.Text() + ", which this case does not have" +
                (writers.empty() ? "" : "; put one of these before it: " + writers));
  }
  const int dim = data.Dim();
  if (!WorksIn(info_->dims, dim))
    throw Error(name + ": works on " + DimsText(info_->dims) + " data, but this case is " + std::to_string(dim) + "D");
  const auto t0 = std::chrono::steady_clock::now();
  try {
    Execute(ctx, data);
  } catch (const Cancelled&) {
    throw;
  } catch (const InputError& e) {
    throw InputError("", 0, Prefixed(name, e.what()));  // keeps its type: the message says FILE:LINE
  } catch (const OptionError& e) {
    throw OptionError(Prefixed(name, e.what()));
  } catch (const std::exception& e) {
    throw Error(Prefixed(name, e.what()));
  }
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  data.stage_seconds.emplace_back(name, s);
  ctx.Log(LogLevel::kDebug, name + ": " + std::to_string(s) + " s");
}

void RunNestedStage(const StageSpec& spec, Context& ctx, CaseData& data, NestedState* carry) {
  if (!data.registry) throw Error("internal: nested stage '" + spec.stage + "' needs the case's registry");
  if (carry) data.nested = *carry;
  data.registry->Create(spec)->Run(ctx, data);
  if (carry) *carry = std::move(data.nested);
}

namespace {
class FnStage : public Stage {
 public:
  FnStage(StageFn fn, ParamMap p) : fn_(std::move(fn)), params_(std::move(p)) {}
  void Execute(Context& ctx, CaseData& data) override { fn_(ctx, data, params_); }

 private:
  StageFn fn_;
  ParamMap params_;
};
}  // namespace

StageInfo DeclareStage(std::string name, Role role, std::string doc, Slots reads, Slots writes, unsigned dims) {
  StageInfo s;
  s.name = std::move(name);
  s.role = role;
  s.doc = std::move(doc);
  s.reads = reads;
  s.writes = writes;
  s.dims = dims;
  s.declared = true;
  return s;
}

StageFactory FunctionStage(StageFn fn) {
  return [fn = std::move(fn)](const ParamMap& p) -> std::unique_ptr<Stage> {
    return std::make_unique<FnStage>(fn, p);
  };
}

}  // namespace arcs
