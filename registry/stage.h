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
  kPointSampler,        // reference mesh -> point cloud (input generation)
  kPointModifier,       // point cloud -> point cloud (noise, outliers, normal estimation)
  kEvaluator,           // output (+ reference, samples) -> metrics
  kOther,
};
const char* RoleName(Role r);
// Parses a role name as printed by RoleName; throws Error if unknown.
Role ParseRole(const std::string& name);

class Registry;

// Everything a case carries from stage to stage.
struct CaseData {
  // The registry the case runs with, so a stage can run a nested stage (e.g.
  // the fine-tuner's reconstructor); see RunNestedStage.
  const Registry* registry = nullptr;
  std::string item;            // dataset item name (file stem)
  std::string item_path;       // dataset file, if any
  std::optional<Mesh> reference;     // ground-truth mesh (normalised)
  std::optional<SdfSamples> samples; // SDF samples
  std::optional<PointCloud> free_points;  // empty-space samples (role kEmptySpaceSampler)
  // RFTA's sign separation (paper §4.1): per row of `free_points`, the sign of
  // the spheres whose free space it samples: +1 = outside all s > 0 spheres,
  // -1 = outside all s < 0 spheres. Empty = every point serves both signs.
  // Free points are in the samples' (input) frame and carry no normals.
  std::vector<signed char> free_point_sign;
  std::optional<PointCloud> points;       // oriented points (projector / fine-tuner output)
  // For RFTA: the SDF sample (sphere) each oriented point belongs to, one per
  // row of `points` (empty when not applicable).
  std::vector<int> point_sample;
  std::optional<Mesh> output;        // the method's output mesh
  // 2D cases (dim 2): the reference curve and the method's output curve,
  // the planar counterparts of `reference` and `output`.
  std::optional<Polyline> reference_curve;
  std::optional<Polyline> output_curve;
  // A voxelizer's output (occupancy or winding numbers on grid nodes).
  std::optional<VolumeGrid> volume;
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

// Runs the nested stage `spec` (a resolved kStage parameter) on `data`, using
// data.registry. Throws Error if the case has no registry.
void RunNestedStage(const StageSpec& spec, Context& ctx, CaseData& data);

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
