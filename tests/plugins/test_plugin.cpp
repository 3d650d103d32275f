// Stages used only by the tests of the runner: they fail, crash or sleep on
// demand, so the runner's handling of bad cases can be checked for real.
#include "registry/plugin_api.h"
#include "registry/registry.h"

#include <chrono>
#include <csignal>
#include <thread>

namespace {

void RegisterStages(arcs::Registry& registry) {
  arcs::StageInfo s;
  s.name = "test_misbehave";
  s.role = arcs::Role::kSdfToMesh;
  s.doc = "test stage: copies the reference mesh as output, or fails / crashes / sleeps on demand";
  s.params.Choice("mode", "ok", {"ok", "throw", "crash", "sleep"}, "what to do")
      .Double("sleep_s", 0.0, "seconds to sleep first", 0.0, 60.0);
  s.factory = arcs::FunctionStage([](arcs::Context&, arcs::CaseData& d, const arcs::ParamMap& p) {
    if (p.GetDouble("sleep_s") > 0)
      std::this_thread::sleep_for(std::chrono::duration<double>(p.GetDouble("sleep_s")));
    const std::string& mode = p.GetString("mode");
    if (mode == "throw") throw arcs::Error("test_misbehave asked to throw");
    if (mode == "crash") std::raise(SIGSEGV);
    d.output = d.RequireReference("test_misbehave");
  });
  registry.Register(std::move(s));
}

}  // namespace

ARCS_PLUGIN("test_plugin", "0.1", RegisterStages)
