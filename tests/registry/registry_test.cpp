#include "registry/registry.h"
#include "stages/builtin.h"

#include <gtest/gtest.h>

namespace arcs {
namespace {

StageInfo Dummy(const std::string& name, const std::string& origin = "builtin") {
  StageInfo s;
  s.name = name;
  s.role = Role::kSdfToMesh;
  s.doc = "dummy";
  s.origin = origin;
  s.params.Int("n", 20, "cells", 1, 100).Double("w", 0.5, "weight", 0.0, 1.0).Choice("mode", "a", {"a", "b"}, "mode");
  s.factory = FunctionStage([](Context&, CaseData&, const ParamMap&) {});
  return s;
}

TEST(RegistryTest, DuplicateNameNamesBothOrigins) {
  Registry r;
  r.Register(Dummy("x", "builtin"));
  try {
    r.Register(Dummy("x", "plugin /tmp/p.so"));
    FAIL() << "expected a duplicate-name error";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("builtin"), std::string::npos) << msg;
    EXPECT_NE(msg.find("/tmp/p.so"), std::string::npos) << msg;
  }
}

TEST(RegistryTest, UnknownStageSuggestsClosest) {
  Registry r;
  RegisterBuiltinStages(r);
  try {
    r.Get("marching_cube");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("did you mean 'marching_cubes'"), std::string::npos) << e.what();
  }
  EXPECT_EQ(r.Suggest("sdf_gird"), "sdf_grid");
  EXPECT_EQ(r.Suggest("completely_unrelated_name"), "");
}

TEST(RegistryTest, ResolveFillsDefaultsAndChecksRanges) {
  Registry r;
  r.Register(Dummy("x"));
  ParamMap given;
  given.Set("n", std::int64_t{7});
  const ParamMap p = r.Resolve("x", given);
  EXPECT_EQ(p.GetInt("n"), 7);
  EXPECT_DOUBLE_EQ(p.GetDouble("w"), 0.5);
  EXPECT_EQ(p.GetString("mode"), "a");

  ParamMap bad;
  bad.Set("n", std::int64_t{1000});
  EXPECT_THROW(r.Resolve("x", bad), OptionError);
  ParamMap bad_choice;
  bad_choice.Set("mode", std::string("c"));
  try {
    r.Resolve("x", bad_choice);
    FAIL();
  } catch (const OptionError& e) {
    EXPECT_NE(std::string(e.what()).find("a|b"), std::string::npos) << e.what();
  }
  ParamMap unknown;
  unknown.Set("nn", std::int64_t{1});
  EXPECT_THROW(r.Resolve("x", unknown), OptionError);
}

TEST(RegistryTest, BuiltinsHaveDocumentedParametersWithValidDefaults) {
  Registry r;
  RegisterBuiltinStages(r);
  const auto list = r.List();
  ASSERT_GE(list.size(), 10u);
  for (const StageInfo* s : list) {
    EXPECT_FALSE(s->doc.empty()) << s->name;
    for (const auto& p : s->params.specs()) {
      EXPECT_FALSE(p.doc.empty()) << s->name << "." << p.name;
      EXPECT_NO_THROW(p.CheckValue(p.default_value)) << s->name << "." << p.name;
    }
    if (s->role == Role::kEvaluator) {
      EXPECT_FALSE(s->outputs.empty()) << s->name;
    }
  }
  // The paper's protocol defaults.
  const StageInfo& g = r.Get("sdf_grid");
  EXPECT_EQ(std::get<std::int64_t>(g.params.Find("n")->default_value), 20);
  EXPECT_EQ(std::get<double>(g.params.Find("lo")->default_value), -1.0);
  EXPECT_EQ(std::get<std::int64_t>(r.Get("chamfer").params.Find("samples")->default_value), 1000000);
}

}  // namespace
}  // namespace arcs
