// The stage contract: a pipeline whose stages cannot feed each other is
// refused before anything runs (Registry::CheckPipeline), naming the missing
// input and the stages that could give it; Stage::Run checks the same at run
// time and prefixes errors with the stage's name once.
#include "registry/registry.h"
#include "stages/builtin.h"

#include "tests/builtin_registry.h"

#include <gtest/gtest.h>

#include <string>

namespace arcs {
namespace {

using testing::Builtins;

std::string PipelineError(const std::vector<std::string>& stages, Slots start, int dim) {
  try {
    Builtins().CheckPipeline(stages, start, dim, [](std::size_t i) { return "exp.yaml:" + std::to_string(10 + i); });
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(PipelineCheck, ArcProjectorWithoutSamplerNamesTheMissingInput) {
  const std::string e = PipelineError({"arc_projector"}, Slots{Slot::kReference, Slot::kSamples}, 3);
  EXPECT_NE(e.find("exp.yaml:10: stage 'arc_projector' needs free_points"), std::string::npos) << e;
  EXPECT_NE(e.find("rasterize"), std::string::npos) << e;  // a stage that writes free points
}

TEST(PipelineCheck, TheRftaPipelineInOrderPasses) {
  EXPECT_EQ(PipelineError({"sdf_grid", "rasterize", "arc_projector", "fine_tune", "screened_poisson", "chamfer"},
                          Slots{Slot::kReference}, 3),
            "");
}

TEST(PipelineCheck, FineTuneBeforeTheProjectorIsRefused) {
  const std::string e =
      PipelineError({"sdf_grid", "rasterize", "fine_tune", "arc_projector"}, Slots{Slot::kReference}, 3);
  EXPECT_NE(e.find("exp.yaml:12: stage 'fine_tune' needs points"), std::string::npos) << e;
}

TEST(PipelineCheck, RunChecksTheContractAndPrefixesOnce) {
  const Registry& r = Builtins();
  Context ctx;
  CaseData d;
  d.registry = &r;
  StageSpec spec{"arc_projector", r.Resolve("arc_projector", ParamMap{})};
  try {
    r.Create(spec)->Run(ctx, d);
    FAIL() << "ran without samples";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind("arc_projector: needs samples, free_points", 0), 0u) << m;
    EXPECT_EQ(m.find("arc_projector: arc_projector"), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace arcs
