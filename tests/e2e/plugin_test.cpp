// Runtime plugins: loaded by --plugin, by the YAML and from $ARCS_PLUGIN_PATH;
// a plugin built against another API version is refused with a clear message.
#include "tests/e2e/e2e_util.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

namespace arcs {
namespace {

using testing::Arcs;
using testing::RunCmd;

TEST(PluginTest, ExamplePluginStageRunsInAnExperiment) {
  const auto dir = testing::TempDir("plugin_run");
  testing::WriteFile(dir / "e.yaml", std::string("name: plug\nplugins: [") + ARCS_EXAMPLE_PLUGIN +
                                         "]\ndatasets: [{shapes: [sphere]}]\n"
                                         "inputs: [{name: grid, pipeline: [{stage: sdf_grid, params: {n: 16}}]}]\n"
                                         "methods: [{name: fit, pipeline: [example_sphere_fit]}]\n"
                                         "metrics: [{stage: chamfer, params: {samples: 20000}}, topology]\n");
  const auto r = RunCmd(Arcs() + " run " + (dir / "e.yaml").string() + " --out " + (dir / "out").string());
  ASSERT_EQ(r.code, 0) << r.output;
  const CsvTable t = ReadCsv((dir / "out" / "results.csv").string());
  ASSERT_EQ(t.rows.size(), 1u);
  EXPECT_EQ(t.Cell(0, "status"), "ok") << t.Cell(0, "error");
  EXPECT_EQ(t.Cell(0, "out_closed"), "1");
  // The built-in sphere has radius 0.5 before normalisation (longest side 1 → radius 0.5):
  // the fitted sphere is close to it.
  EXPECT_LT(std::stod(t.Cell(0, "chamfer")), 0.1);
  EXPECT_NE(testing::ReadFile(dir / "out" / "provenance.yaml").find("example_sphere_fit"), std::string::npos);
}

TEST(PluginTest, LoadedFromCommandLineAndSearchPath) {
  const auto l = RunCmd(Arcs() + " list --plugin " + ARCS_EXAMPLE_PLUGIN);
  ASSERT_EQ(l.code, 0) << l.output;
  EXPECT_NE(l.output.find("example_sphere_fit"), std::string::npos);
  const auto dir = testing::TempDir("plugin_path");
  std::filesystem::copy_file(ARCS_EXAMPLE_PLUGIN, dir / "libexample.so");
  const auto p = RunCmd("ARCS_PLUGIN_PATH=" + dir.string() + " " + Arcs() + " describe example_sphere_fit");
  ASSERT_EQ(p.code, 0) << p.output;
  EXPECT_NE(p.output.find("subdivisions"), std::string::npos) << p.output;
}

TEST(PluginTest, WrongApiVersionIsRefusedClearly) {
  const auto r = RunCmd(Arcs() + " list --plugin " + ARCS_WRONG_API_PLUGIN);
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.output.find("API version 999"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("rebuild the plugin"), std::string::npos) << r.output;
  const auto missing = RunCmd(Arcs() + " list --plugin /nonexistent/libx.so");
  EXPECT_NE(missing.code, 0);
  EXPECT_NE(missing.output.find("not found"), std::string::npos) << missing.output;
}

}  // namespace
}  // namespace arcs
