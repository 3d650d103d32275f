// The stage interface: a named, parameterised step of a pipeline.
//
// A stage is a thin adaptor: it decodes its resolved parameters into an
// algorithm's Options struct and calls the algorithm on the case's data.
#pragma once

#include "framework/context.h"
#include "framework/types.h"
#include "registry/param.h"

#include <functional>
#include <map>
#include <optional>
#include <memory>
#include <string>
#include <vector>

namespace arcs {

// What a stage consumes and produces (the arrows of DESIGN.md's pipeline).
enum class Role {
  kSdfSampler,          // reference mesh -> SDF samples
  kSdfModifier,         // SDF samples -> SDF samples (noise, clamp, ...)
  kSdfToMesh,           // SDF samples -> output mesh (baselines such as marching cubes)
  kEmptySpaceSampler,   // SDF samples -> free-space samples
  kArcProjector,        // SDF samples + free samples -> oriented points
  kFineTuner,           // oriented points -> oriented points
  kReconstructor,       // oriented points -> output mesh
  kVoxelizer,           // mesh -> occupancy grid
  kEvaluator,           // output (+ reference, samples) -> metrics
  kOther,
};
const char* RoleName(Role r);
// Parses a role name as printed by RoleName; throws Error if unknown.
Role ParseRole(const std::string& name);

// Everything a case carries from stage to stage.
struct CaseData {
  std::string item;            // dataset item name (file stem)
  std::string item_path;       // dataset file, if any
  std::optional<Mesh> reference;     // ground-truth mesh (normalised)
  std::optional<SdfSamples> samples; // SDF samples
  std::optional<PointCloud> free_points;  // empty-space samples (role kEmptySpaceSampler)
  std::optional<PointCloud> points;       // oriented points (projector / fine-tuner output)
  std::optional<Mesh> output;        // the method's output mesh
  // Metrics and facts in insertion order; the runner writes them as columns.
  std::vector<std::pair<std::string, double>> metrics;

  void SetMetric(const std::string& name, double v);
  const Mesh& RequireReference(const std::string& stage) const;
  const SdfSamples& RequireSamples(const std::string& stage) const;
  const Mesh& RequireOutput(const std::string& stage) const;
};

class Stage {
 public:
  virtual ~Stage() = default;
  virtual void Run(Context& ctx, CaseData& data) = 0;
};

using StageFactory = std::function<std::unique_ptr<Stage>(const ParamMap&)>;

struct StageInfo {
  std::string name;
  Role role = Role::kOther;
  std::string doc;                   // one line
  ParamSchema params;
  std::vector<std::string> outputs;  // metric columns an evaluator writes
  StageFactory factory;
  std::string origin = "builtin";    // or the plugin file that registered it
};

// A stage from a plain function: the common case for thin adaptors.
using StageFn = std::function<void(Context&, CaseData&, const ParamMap&)>;
StageFactory FunctionStage(StageFn fn);

}  // namespace arcs
