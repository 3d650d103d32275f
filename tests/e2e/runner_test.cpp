// The runner's handling of failing, crashing, slow and interrupted cases,
// checked through the real `arcs` program with a misbehaving test plugin.
#include "tests/e2e/e2e_util.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <thread>
#include <unistd.h>

namespace arcs {
namespace {

using testing::Arcs;
using testing::RunCmd;

std::string Yaml(const std::string& modes, double timeout = 0, const std::string& sleep = "0") {
  return std::string("name: misbehave\nplugins: [") + ARCS_TEST_PLUGIN + "]\n" +
         (timeout > 0 ? "case_timeout_s: " + std::to_string(timeout) + "\n" : "") +
         "datasets: [{shapes: [sphere]}]\n"
         "methods:\n  - name: m\n    pipeline:\n      - stage: test_misbehave\n        params: {mode: " + modes +
         ", sleep_s: " + sleep + "}\nmetrics: [mesh_size]\n";
}

TEST(RunnerTest, FailuresAndCrashesAreRecordedAndTheRunGoesOn) {
  const auto dir = testing::TempDir("runner_fail");
  testing::WriteFile(dir / "e.yaml", Yaml("[throw, crash, ok]"));
  const auto r = RunCmd(Arcs() + " run " + (dir / "e.yaml").string() + " --out " + (dir / "out").string());
  ASSERT_EQ(r.code, 0) << r.output;
  const CsvTable t = ReadCsv((dir / "out" / "results.csv").string());
  ASSERT_EQ(t.rows.size(), 3u) << r.output;
  std::map<std::string, std::pair<std::string, std::string>> by_mode;
  for (size_t i = 0; i < t.rows.size(); ++i)
    by_mode[t.Cell(i, "test_misbehave.mode")] = {t.Cell(i, "status"), t.Cell(i, "error")};
  EXPECT_EQ(by_mode["ok"].first, "ok");
  EXPECT_EQ(by_mode["throw"].first, "failed");
  EXPECT_NE(by_mode["throw"].second.find("asked to throw"), std::string::npos) << by_mode["throw"].second;
  EXPECT_EQ(by_mode["crash"].first, "failed");
  EXPECT_NE(by_mode["crash"].second.find("signal 11"), std::string::npos) << by_mode["crash"].second;
  // The successful case carries its metrics and its method's time and memory.
  for (size_t i = 0; i < t.rows.size(); ++i) {
    if (t.Cell(i, "status") != "ok") continue;
    EXPECT_GT(std::stoi(t.Cell(i, "out_faces")), 1000);
    EXPECT_FALSE(t.Cell(i, "method_wall_s").empty());
    EXPECT_GT(std::stod(t.Cell(i, "peak_rss_mb")), 1.0);
  }
  // Failed cases are not retried unless asked.
  const auto again = RunCmd(Arcs() + " run " + (dir / "e.yaml").string() + " --out " + (dir / "out").string());
  EXPECT_NE(again.output.find("3 skipped"), std::string::npos) << again.output;
  const auto retry = RunCmd(Arcs() + " run " + (dir / "e.yaml").string() + " --retry-failed --out " +
                            (dir / "out").string());
  EXPECT_NE(retry.output.find("1 skipped"), std::string::npos) << retry.output;
}

TEST(RunnerTest, SlowCaseTimesOut) {
  const auto dir = testing::TempDir("runner_timeout");
  testing::WriteFile(dir / "e.yaml", Yaml("[ok]", 0.5, "[0, 20]"));
  const auto start = std::chrono::steady_clock::now();
  const auto r = RunCmd(Arcs() + " run " + (dir / "e.yaml").string() + " --out " + (dir / "out").string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 15.0);
  const CsvTable t = ReadCsv((dir / "out" / "results.csv").string());
  ASSERT_EQ(t.rows.size(), 2u);
  int timed_out = 0;
  for (size_t i = 0; i < t.rows.size(); ++i) timed_out += t.Cell(i, "error").find("timed out") != std::string::npos;
  EXPECT_EQ(timed_out, 1);
}

TEST(RunnerTest, InterruptedRunResumesWithoutRedoingFinishedCases) {
  const auto dir = testing::TempDir("runner_interrupt");
  // Six cases of ~1 s each.
  testing::WriteFile(dir / "e.yaml", Yaml("ok", 0, "[1.0, 1.01, 1.02, 1.03, 1.04, 1.05]"));
  const std::string out = (dir / "out").string();
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    const std::string cmd = Arcs() + " run " + (dir / "e.yaml").string() + " --quiet --out " + out + " >/dev/null 2>&1";
    execl("/bin/sh", "sh", "-c", ("exec " + cmd).c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  // Wait until two rows are written, then interrupt.
  const auto csv = std::filesystem::path(out) / "results.csv";
  for (int i = 0; i < 300; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    if (std::filesystem::exists(csv) && ReadCsv(csv.string()).rows.size() >= 2) break;
  }
  kill(pid, SIGINT);
  int status = 0;
  waitpid(pid, &status, 0);
  const size_t before = ReadCsv(csv.string()).rows.size();
  ASSERT_GE(before, 2u);
  ASSERT_LT(before, 6u) << "the interrupt came too late to test anything";
  const auto r = RunCmd(Arcs() + " run " + (dir / "e.yaml").string() + " --out " + out);
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find(std::to_string(before) + " skipped"), std::string::npos) << r.output;
  const CsvTable t = ReadCsv(csv.string());
  EXPECT_EQ(t.rows.size(), 6u);
  std::set<std::string> ids;
  for (size_t i = 0; i < t.rows.size(); ++i) ids.insert(t.Cell(i, "case_id"));
  EXPECT_EQ(ids.size(), 6u) << "no case was run twice";
}

}  // namespace
}  // namespace arcs
