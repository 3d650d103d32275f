// Every experiment file shipped in experiments/ validates and expands, and
// each table's rows/columns name a column the cases will have.
#include "orchestration/expand.h"
#include "orchestration/spec.h"
#include "stages/builtin.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace arcs {
namespace {

bool HasColumn(const Case& c, const std::string& name) {
  // Columns the runner writes for every case (ref_* describe the reference).
  static const std::vector<std::string> fixed = {"method", "item", "dataset", "input", "seed",
                                                 "ref_genus", "ref_faces", "ref_closed", "ref_components"};
  if (std::find(fixed.begin(), fixed.end(), name) != fixed.end()) return true;
  for (const auto& [k, v] : c.params)
    if (k == name || (k.size() > name.size() && k.compare(k.size() - name.size() - 1, std::string::npos, "." + name) == 0))
      return true;
  return false;
}

TEST(ExperimentFilesTest, AllShippedExperimentsValidateAndExpand) {
  int checked = 0;
  for (const auto& entry : std::filesystem::directory_iterator(ARCS_SOURCE_DIR "/experiments")) {
    if (entry.path().extension() != ".yaml") continue;
    std::ifstream in(entry.path());
    std::stringstream text;
    text << in.rdbuf();
    if (text.str().find("ARCS_SHARED_DIR") != std::string::npos && testing::SharedDir().empty()) continue;
    SCOPED_TRACE(entry.path().string());
    Registry registry;
    RegisterBuiltinStages(registry);
    const Experiment exp = LoadExperiment(entry.path().string(), {}, registry);
    const auto cases = ExpandCases(exp, registry);
    ASSERT_FALSE(cases.empty());
    for (const auto& t : exp.tables) {
      EXPECT_TRUE(HasColumn(cases[0], t.rows)) << "table " << t.name << ": rows '" << t.rows << "'";
      EXPECT_TRUE(HasColumn(cases[0], t.columns)) << "table " << t.name << ": columns '" << t.columns << "'";
    }
    ++checked;
  }
  EXPECT_GE(checked, 1);
}

}  // namespace
}  // namespace arcs
