// The table of 2D twins (stages/twins_2d.h): every pair is registered with
// the same role, and every registered stage whose name ends in _2d is the
// twin of a 3D stage (so the table is the one place to look).
#include "registry/registry.h"
#include "stages/builtin.h"
#include "stages/twins_2d.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

namespace arcs {
namespace {

TEST(Twins2D, PairsAreRegisteredWithTheSameRole) {
  Registry r;
  RegisterBuiltinStages(r);
  std::set<std::string> twins;
  for (const StageTwin& t : kStageTwins2D) {
    ASSERT_NE(r.Find(t.stage_3d), nullptr) << t.stage_3d;
    ASSERT_NE(r.Find(t.stage_2d), nullptr) << t.stage_2d;
    EXPECT_EQ(r.Get(t.stage_3d).role, r.Get(t.stage_2d).role) << t.stage_3d << " / " << t.stage_2d;
    EXPECT_EQ(TwinIn2D(t.stage_3d), t.stage_2d);
    twins.insert(t.stage_2d);
  }
  EXPECT_EQ(TwinIn2D("rasterize"), "");  // one stage for both dimensions
  for (const StageInfo* s : r.List()) {
    const std::string& n = s->name;
    if (n.size() > 3 && n.compare(n.size() - 3, 3, "_2d") == 0) {
      EXPECT_TRUE(twins.count(n)) << n << " is not in kStageTwins2D";
    }
  }
}

}  // namespace
}  // namespace arcs
