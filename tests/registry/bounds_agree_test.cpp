// Every stage's declared bounds agree with its algorithm's own Check() at
// both ends of every numeric parameter (issue 11: a value the schema accepts
// must not fail at run time, and the other way round).
//
// For each built-in stage with a load-time check (StageInfo::check, set by
// BindStage from the parameter binder) and each int/double parameter with a
// finite end: the value AT a closed end (or just inside an open one) passes
// the algorithm's check, and the value just BEYOND it (or at an open end)
// fails it. The check is called directly, bypassing the schema's own bounds
// test, so the algorithm's Check() alone has to refuse it.
#include "registry/registry.h"
#include "stages/builtin.h"

#include "tests/builtin_registry.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

namespace arcs {
namespace {

using testing::Builtins;

// Whether info.check accepts `params` with `name` set to v (int or double).
bool Accepts(const StageInfo& info, ParamMap params, const ParamSpec& spec, double v, std::string* why) {
  if (spec.type == ParamType::kInt)
    params.Set(spec.name, static_cast<std::int64_t>(v));
  else
    params.Set(spec.name, v);
  try {
    info.check(params);
    return true;
  } catch (const std::exception& e) {
    *why = e.what();
    return false;
  }
}

TEST(BoundsAgree, EveryBoundStageAtBothEnds) {
  const Registry& r = Builtins();
  int stages = 0, ends = 0;
  std::string failures;
  for (const StageInfo* info : r.List()) {
    if (!info->check) continue;
    ++stages;
    const ParamMap defaults = r.Resolve(info->name, ParamMap{});
    for (const ParamSpec& spec : info->params.specs()) {
      if (spec.type != ParamType::kInt && spec.type != ParamType::kDouble) continue;
      const bool is_int = spec.type == ParamType::kInt;
      // An int end at the 64-bit limit has no value beyond it.
      const double big = 9.2e18;
      for (int side = 0; side < 2; ++side) {
        const double end = side == 0 ? spec.min : spec.max;
        const bool open = side == 0 ? spec.min_open : spec.max_open;
        if (!std::isfinite(end) || std::fabs(end) >= big) continue;
        const double outward = side == 0 ? -std::numeric_limits<double>::infinity()
                                         : std::numeric_limits<double>::infinity();
        const double step = is_int ? (side == 0 ? -1.0 : 1.0) : 0.0;
        const double inside = open ? (is_int ? end - step : std::nextafter(end, -outward)) : end;
        const double beyond = open ? end : (is_int ? end + step : std::nextafter(end, outward));
        // An int field narrower than 64 bits: its type's end has nothing beyond.
        const bool type_end = is_int && std::fabs(end) >= 2147483647.0 && std::fabs(end) <= 2147483648.0;
        ++ends;
        std::string why;
        const std::string where = info->name + "." + spec.name + " " + spec.RangeText();
        if (!Accepts(*info, defaults, spec, inside, &why))
          failures += where + ": the algorithm refuses " + std::to_string(inside) + " (" + why + ")\n";
        if (!type_end && Accepts(*info, defaults, spec, beyond, &why))
          failures += where + ": the algorithm accepts " + std::to_string(beyond) + ", outside the declared bounds\n";
      }
    }
  }
  EXPECT_TRUE(failures.empty()) << failures;
  // The walk must have covered the bound stages (a walk over nothing passes trivially).
  EXPECT_GE(stages, 2) << "no stage declares its parameters through the binder";
  EXPECT_GE(ends, 10);
  std::printf("checked %d ends of %d bound stages\n", ends, stages);
}

// The drift issue 11 found: arc_projector's tol = 0.1 passed the schema
// ([0, 0.1]) and failed at run time ([0, 0.1)). Now Resolve refuses it.
TEST(BoundsAgree, ArcProjectorTolAtItsOpenEndIsRefusedByResolve) {
  const Registry& r = Builtins();
  ParamMap given;
  given.Set("tol", 0.1);
  try {
    r.Resolve("arc_projector", given);
    FAIL() << "tol = 0.1 was accepted";
  } catch (const OptionError& e) {
    EXPECT_NE(std::string(e.what()).find("arc_projector.tol = 0.1"), std::string::npos) << e.what();
  }
  given.Set("tol", 0.0999);
  EXPECT_NO_THROW(r.Resolve("arc_projector", given));
  ParamMap ft;
  ft.Set("tol", 0.1);
  EXPECT_THROW(r.Resolve("fine_tune", ft), OptionError);
}

}  // namespace
}  // namespace arcs
