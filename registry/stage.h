// The stage interface: a named, parameterised step of a pipeline.
//
// A stage is a thin adaptor: it decodes its resolved parameters into an
// algorithm's Options struct (registry/bind.h) and calls the algorithm on
// the case's data. Its contract is declared in StageInfo: the CaseData
// slots it reads and writes and the dimensions it works in. The loader
// checks a pipeline's data flow against it before any case runs
// (CheckPipeline, registry/registry.h), and Stage::Run checks it again,
// with the stop flag, the stage's time and one prefix on its errors.
#pragma once

#include "framework/context.h"
#include "framework/types.h"
#include "registry/param.h"

#include <functional>
#include <initializer_list>
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

// The values of CaseData a stage reads or writes (its data-flow contract).
enum class Slot : unsigned {
  kReference = 1u << 0,   // the reference shape: `reference` (3D) or `reference_curve` (2D)
  kSamples = 1u << 1,     // `samples`: SDF samples
  kFreePoints = 1u << 2,  // `free_points` (+ `free_point_sign`): empty-space samples
  kPoints = 1u << 3,      // `points` (+ `point_sample`): a point cloud or tangency points
  kOutput = 1u << 4,      // the method's output: `output` (3D) or `output_curve` (2D)
  kVolume = 1u << 5,      // `volume`: a voxelizer's grid
};
inline constexpr Slot kAllSlots[] = {Slot::kReference, Slot::kSamples, Slot::kFreePoints,
                                     Slot::kPoints,    Slot::kOutput,  Slot::kVolume};
// "reference", "samples", "free_points", "points", "output", "volume".
const char* SlotName(Slot s);

// A set of slots.
class Slots {
 public:
  constexpr Slots() = default;
  constexpr Slots(std::initializer_list<Slot> l) {
    for (Slot s : l) bits_ |= static_cast<unsigned>(s);
  }
  constexpr bool Has(Slot s) const { return bits_ & static_cast<unsigned>(s); }
  constexpr bool Empty() const { return bits_ == 0; }
  constexpr Slots operator|(Slots o) const { return FromBits(bits_ | o.bits_); }
  // The slots of this set that `present` lacks.
  constexpr Slots Without(Slots present) const { return FromBits(bits_ & ~present.bits_); }
  constexpr bool operator==(const Slots&) const = default;
  // "samples, free_points" (empty set: "nothing").
  std::string Text() const;

 private:
  static constexpr Slots FromBits(unsigned b) {
    Slots s;
    s.bits_ = b;
    return s;
  }
  unsigned bits_ = 0;
};

// The dimensions a stage works in (a bit set).
enum Dims : unsigned { k2D = 1u, k3D = 2u, kAnyDim = 3u };
// "2D", "3D", "2D and 3D".
std::string DimsText(unsigned dims);
// Whether a stage of `dims` works on data of dimension `dim` (0 = not known: yes).
inline bool WorksIn(unsigned dims, int dim) { return dim == 0 || (dims & (dim == 2 ? k2D : k3D)); }
// Whether an error message already names `stage` ("stage: ..." or "stage.param ...").
bool NamesStage(const std::string& what, const std::string& stage);

// State a stage keeps between repeated nested calls for one case: only the
// stage named `owner` (the one that wrote it) reads it.
struct NestedState {
  std::shared_ptr<void> state;
  std::string owner;
};

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
  // What a nested stage may keep between the calls one caller makes for this
  // case (RFTA's fine-tuning reconstructor warm-starts its solve from the
  // previous iteration's); RunNestedStage carries it from call to call.
  NestedState nested;
  // Wall time of every stage that ran on this case (nested ones included),
  // in the order they finished; recorded by Stage::Run.
  std::vector<std::pair<std::string, double>> stage_seconds;

  void SetMetric(const std::string& name, double v);
  // The slots that hold a value now.
  Slots Present() const;
  // The case's dimension: the samples', else 2 for a curve, 3 for a mesh or
  // volume, 0 when nothing tells (e.g. a point cloud alone).
  int Dim() const;
  const Mesh& RequireReference(const std::string& stage) const;
  const SdfSamples& RequireSamples(const std::string& stage) const;
  const Mesh& RequireOutput(const std::string& stage) const;
};

struct StageInfo;

class Stage {
 public:
  virtual ~Stage() = default;
  // The contract, the same for every stage (not virtual): throws Cancelled if
  // a stop was requested; with the stage's StageInfo attached (Registry::
  // Create does that), throws Error naming the missing input when a declared
  // read slot is empty or the case's dimension is not one the stage works in;
  // runs Execute; records its wall time in CaseData::stage_seconds; and
  // prefixes an error from Execute with "NAME: " unless it already starts so.
  void Run(Context& ctx, CaseData& data);
  // The stage's declaration (null for a stage made by its factory alone).
  const StageInfo* info() const { return info_; }
  void set_info(const StageInfo* info) { info_ = info; }

 protected:
  virtual void Execute(Context& ctx, CaseData& data) = 0;

 private:
  const StageInfo* info_ = nullptr;
};

using StageFactory = std::function<std::unique_ptr<Stage>(const ParamMap&)>;

// Runs the nested stage `spec` (a resolved kStage parameter) on `data`, using
// data.registry. Throws Error if the case has no registry. `carry`
// (optional): the stage's NestedState from the previous call goes in, this
// call's comes back (a caller calling the same stage repeatedly).
void RunNestedStage(const StageSpec& spec, Context& ctx, CaseData& data, NestedState* carry = nullptr);

struct StageInfo {
  std::string name;
  Role role = Role::kOther;
  std::string doc;                   // one line
  ParamSchema params;
  std::vector<std::string> outputs;  // metric columns an evaluator writes
  StageFactory factory;
  std::string origin = "builtin";    // or the plugin file that registered it
  // The contract. `reads`: slots that must hold a value before the stage
  // runs; `writes`: slots it fills; `dims`: the dimensions it works in.
  // `declared`: false for a stage that says nothing of its data flow (an
  // older plugin); the pipeline check stops at such a stage.
  Slots reads;
  Slots writes;
  unsigned dims = kAnyDim;
  bool declared = false;
  // The algorithm's own check of resolved parameters (decode into Options,
  // Options::Check()); run by Registry::Resolve, i.e. at load time. Null:
  // the schema's bounds are the whole check. Set by BindStage.
  std::function<void(const ParamMap&)> check;
};

// A StageInfo with its contract declared (declared = true); the caller adds
// the parameters and the factory (BindStage, registry/bind.h, does both).
StageInfo DeclareStage(std::string name, Role role, std::string doc, Slots reads, Slots writes,
                       unsigned dims = kAnyDim);

// A stage from a plain function: the common case for thin adaptors.
using StageFn = std::function<void(Context&, CaseData&, const ParamMap&)>;
StageFactory FunctionStage(StageFn fn);

}  // namespace arcs
