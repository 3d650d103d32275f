// Sharded runs and one results directory with many writers, through the real
// `arcs` program: --dry-run/--shard on the quickstart, concurrent runners,
// another experiment refused, kill -9 at any moment, a torn last row, table
// names, threads from the CPU allocation, directories from before sharding.
#include "tests/e2e/e2e_util.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <map>
#include <set>
#include <sstream>
#include <thread>

namespace arcs {
namespace {

namespace fs = std::filesystem;
using testing::Arcs;
using testing::RunCmd;

// Cases that sleep `sleeps` seconds each (the test plugin), one per value.
std::string Yaml(const std::string& sleeps, const std::string& extra = "") {
  return std::string("name: shards\nplugins: [") + ARCS_TEST_PLUGIN + "]\n"
         "datasets: [{shapes: [sphere]}]\n"
         "methods:\n  - name: m\n    pipeline:\n      - stage: test_misbehave\n        params: {mode: ok, sleep_s: " +
         sleeps + "}\nmetrics: [mesh_size]\n" + extra;
}

// Case ids of a --dry-run listing.
std::vector<std::string> ListedIds(const std::string& output) {
  std::vector<std::string> ids;
  std::istringstream in(output);
  std::string line;
  while (std::getline(in, line))
    if (line.size() > 17 && line[16] == '\t' && line.find_first_not_of("0123456789abcdef") == 16)
      ids.push_back(line.substr(0, 16));
  return ids;
}

// Case id -> how many rows have it, over every results file of `dir` (raw
// files, not the deduplicating reader: a case computed twice shows here).
std::map<std::string, int> RowsPerCase(const fs::path& dir) {
  std::map<std::string, int> n;
  if (!fs::exists(dir)) return n;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string f = e.path().filename().string();
    if (f.rfind("results", 0) != 0 || e.path().extension() != ".csv") continue;
    const CsvTable t = ReadCsv(e.path().string());
    for (size_t r = 0; r < t.rows.size(); ++r) ++n[t.Cell(r, "case_id")];
  }
  return n;
}

pid_t Spawn(const std::string& cmd) {
  const pid_t pid = fork();
  if (pid == 0) {
    setpgid(0, 0);
    execl("/bin/sh", "sh", "-c", ("exec " + cmd + " >/dev/null 2>&1").c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  return pid;
}

int Wait(pid_t pid) {
  int st = 0;
  waitpid(pid, &st, 0);
  return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
}

TEST(ShardCliTest, DryRunListsTheQuickstartAndItsShardsPartitionIt) {
  const std::string exp = std::string(ARCS_SOURCE_DIR) + "/experiments/quickstart.yaml";
  const auto all = RunCmd(Arcs() + " run " + exp + " --dry-run --out " + testing::TempDir("dry").string());
  ASSERT_EQ(all.code, 0) << all.output;
  const auto ids = ListedIds(all.output);
  EXPECT_EQ(ids.size(), 16u) << all.output;  // 4 shapes x 2 n x (MC, RFTA)
  EXPECT_NE(all.output.find("\n16 cases\n"), std::string::npos) << all.output;
  EXPECT_EQ(std::set<std::string>(ids.begin(), ids.end()).size(), 16u);
  EXPECT_FALSE(fs::exists(testing::TempDir("dry") / "results.csv")) << "a dry run writes nothing";
  std::multiset<std::string> from_shards;
  for (int i = 0; i < 3; ++i) {
    const auto s = RunCmd(Arcs() + " run " + exp + " --dry-run --shard " + std::to_string(i) + "/3");
    ASSERT_EQ(s.code, 0) << s.output;
    const auto part = ListedIds(s.output);
    // 16 cases over 3 shards: 5 or 6 each.
    EXPECT_GE(part.size(), 5u) << s.output;
    EXPECT_LE(part.size(), 6u) << s.output;
    from_shards.insert(part.begin(), part.end());
    // The Slurm array task's environment gives the same shard.
    const auto env = RunCmd("SLURM_ARRAY_TASK_ID=" + std::to_string(i) + " SLURM_ARRAY_TASK_COUNT=3 " + Arcs() +
                            " run " + exp + " --dry-run");
    EXPECT_EQ(ListedIds(env.output), part) << env.output;
  }
  EXPECT_EQ(from_shards, std::multiset<std::string>(ids.begin(), ids.end())) << "each case in exactly one shard";
  const auto bad = RunCmd(Arcs() + " run " + exp + " --dry-run --shard 3/3");
  EXPECT_EQ(bad.code, 1);
  EXPECT_NE(bad.output.find("0 <= I < N"), std::string::npos) << bad.output;
}

TEST(ShardCliTest, ConcurrentRunnersOnOneDirectory) {
  const auto dir = testing::TempDir("shards_concurrent");
  testing::WriteFile(dir / "e.yaml", Yaml("[0.8, 0.81, 0.82, 0.83, 0.84, 0.85, 0.86, 0.87]"));
  const std::string base = Arcs() + " run " + (dir / "e.yaml").string() + " --out " + (dir / "out").string();
  const pid_t a = Spawn(base + " --shard 0/2");
  // Wait until shard 0 holds its lock (its first row or its lock file's note).
  const fs::path lock = dir / "out" / "locks" / "results.0-of-2.csv.lock";
  for (int i = 0; i < 200 && !(fs::exists(lock) && fs::file_size(lock) > 0); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(25));
  const auto twice = RunCmd(base + " --shard 0/2");
  EXPECT_EQ(twice.code, 1) << twice.output;
  EXPECT_NE(twice.output.find("shard 0/2 of this directory is already being run"), std::string::npos) << twice.output;
  EXPECT_NE(twice.output.find("pid " + std::to_string(a)), std::string::npos) << twice.output;
  const pid_t b = Spawn(base + " --shard 1/2");
  EXPECT_EQ(Wait(a), 0);
  EXPECT_EQ(Wait(b), 0);
  const auto rows = RowsPerCase(dir / "out");
  EXPECT_EQ(rows.size(), 8u);
  for (const auto& [id, n] : rows) EXPECT_EQ(n, 1) << id << " computed " << n << " times";
  EXPECT_TRUE(fs::exists(dir / "out" / "results.0-of-2.csv"));
  EXPECT_TRUE(fs::exists(dir / "out" / "results.1-of-2.csv"));
  EXPECT_FALSE(fs::exists(dir / "out" / "tmp")) << "each runner removes only its own scratch; the last leaves none";
  // Every row says where it ran; provenance has one document per run (3 runs started).
  const CsvTable t = ReadCsv((dir / "out" / "results.0-of-2.csv").string());
  ASSERT_GT(t.rows.size(), 0u);
  EXPECT_EQ(t.Cell(0, "shard"), "0/2");
  EXPECT_FALSE(t.Cell(0, "host").empty());
  EXPECT_FALSE(t.Cell(0, "git_revision").empty());
  const std::string prov = testing::ReadFile(dir / "out" / "provenance.yaml");
  size_t docs = 0;
  for (size_t p = prov.find("---\n"); p != std::string::npos; p = prov.find("---\n", p + 1)) ++docs;
  EXPECT_EQ(docs, 2u) << "the refused runner appends nothing\n" << prov;
  // The union: all shards done, nothing left to run.
  const auto again = RunCmd(base + " --dry-run");
  EXPECT_EQ(again.output.find("\ttodo"), std::string::npos) << again.output;
  const auto resume = RunCmd(base);
  EXPECT_NE(resume.output.find("8 skipped"), std::string::npos) << resume.output;
  // Another experiment into the same directory is refused, and changes nothing.
  const auto other = RunCmd(base + " --set seed=2");
  EXPECT_EQ(other.code, 1);
  EXPECT_NE(other.output.find("holds the results of another experiment"), std::string::npos) << other.output;
  EXPECT_EQ(RowsPerCase(dir / "out").size(), 8u);
}

TEST(ShardCliTest, KillNineAtAnyMomentThenTheSameCommandKeepsEveryFinishedCaseOnce) {
  const auto dir = testing::TempDir("shards_kill9");
  testing::WriteFile(dir / "e.yaml", Yaml("[0.15, 0.16, 0.17, 0.18, 0.19, 0.2, 0.21, 0.22, 0.23, 0.24]"));
  const std::string cmd =
      Arcs() + " run " + (dir / "e.yaml").string() + " --jobs 2 --out " + (dir / "out").string();
  std::set<std::string> finished;
  // Kill moments by progress, not by the clock (the machine may be busy):
  // at once, once the runner holds its lock, and after 1, 2 and 3 more rows.
  const fs::path lock = dir / "out" / "locks" / "results.csv.lock";
  for (int more : {-2, -1, 1, 2, 3}) {
    const size_t before = RowsPerCase(dir / "out").size();
    const pid_t pid = Spawn(cmd);
    bool exited = false;
    for (int i = 0; more > -2 && i < 6000; ++i) {
      if (more == -1 ? fs::exists(lock) && fs::file_size(lock) > 0
                     : RowsPerCase(dir / "out").size() >= before + static_cast<size_t>(more))
        break;
      if (waitpid(pid, nullptr, WNOHANG) == pid) {  // finished before the moment came
        exited = true;
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    if (!exited) {
      kill(pid, SIGKILL);  // the runner only: its workers die with it (PR_SET_PDEATHSIG)
      waitpid(pid, nullptr, 0);
    }
    for (const auto& [id, n] : RowsPerCase(dir / "out")) {
      EXPECT_EQ(n, 1) << id << " after a kill (moment " << more << ")";
      finished.insert(id);
    }
  }
  const auto r = RunCmd(cmd);
  ASSERT_EQ(r.code, 0) << r.output;
  const auto rows = RowsPerCase(dir / "out");
  EXPECT_EQ(rows.size(), 10u);
  for (const auto& [id, n] : rows) EXPECT_EQ(n, 1) << id;
  for (const auto& id : finished) EXPECT_EQ(rows.count(id), 1u) << "finished case " << id << " lost";
  EXPECT_GT(finished.size(), 0u) << "no kill came after a finished case: the test checked nothing";
  EXPECT_NE(r.output.find(std::to_string(finished.size()) + " skipped"), std::string::npos) << r.output;
}

TEST(ShardCliTest, ATornLastRowIsRepairedOnResume) {
  const auto dir = testing::TempDir("shards_torn");
  testing::WriteFile(dir / "e.yaml",
                     Yaml("[0, 0.01, 0.02, 0.03]", "tables:\n  - {name: t, metrics: [out_faces], rows: sleep_s}\n"));
  const std::string cmd = Arcs() + " run " + (dir / "e.yaml").string() + " --out " + (dir / "out").string();
  ASSERT_EQ(RunCmd(cmd).code, 0);
  const fs::path csv = dir / "out" / "results.csv";
  std::string text = testing::ReadFile(csv);
  const size_t last = text.rfind('\n', text.size() - 2) + 1;
  const std::string torn_id = text.substr(last, 16);
  testing::WriteFile(csv, text.substr(0, last + (text.size() - last) / 2));  // half of the last row
  const auto table = RunCmd(Arcs() + " table " + (dir / "out").string());
  EXPECT_EQ(table.code, 0) << "readers skip a torn tail: " << table.output;
  const auto r = RunCmd(cmd);
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("last row was incomplete"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("3 skipped"), std::string::npos) << r.output;
  const CsvTable t = ReadCsv(csv.string());  // parses: a valid file
  ASSERT_EQ(t.rows.size(), 4u);
  std::set<std::string> ids;
  for (size_t i = 0; i < t.rows.size(); ++i) ids.insert(t.Cell(i, "case_id"));
  EXPECT_EQ(ids.size(), 4u);
  EXPECT_EQ(ids.count(torn_id), 1u);
}

TEST(ShardCliTest, TableMistakesAndEscapingNamesAreRefusedBeforeAnyCase) {
  const auto dir = testing::TempDir("shards_tables");
  for (const auto& [table, piece] : std::vector<std::pair<std::string, std::string>>{
           {"{name: ../../../x, metrics: [out_faces], rows: item}", "contains '..'"},
           {"{name: t, metrics: [out_faces], rows: itme}", "rows column 'itme'"},
           {"{name: t, metrics: [out_faces], rows: item, groups: [{name: g, where: \"ref_gnus > 0\"}]}", "where"}}) {
    testing::WriteFile(dir / "e.yaml", Yaml("[0, 0.01]", "tables:\n  - " + table + "\n"));
    const auto r = RunCmd(Arcs() + " run " + (dir / "e.yaml").string() + " --out " + (dir / "out").string());
    EXPECT_EQ(r.code, 1) << table;
    EXPECT_NE(r.output.find(piece), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / "out" / "results.csv")) << "no case ran: " << table;
  }
  EXPECT_FALSE(fs::exists(dir.parent_path().parent_path() / "x.md"));
}

TEST(ShardCliTest, ThreadsComeFromTheCpuAllocation) {
  const auto dir = testing::TempDir("shards_threads");
  testing::WriteFile(dir / "e.yaml", Yaml("[0]"));
  const std::string run = Arcs() + " run " + (dir / "e.yaml").string() + " --out ";
  struct Way {
    std::string prefix, out, from;
  };
  for (const Way& w : {Way{"taskset -c 0 ", "pinned", "sched_getaffinity"},
                       Way{"SLURM_CPUS_PER_TASK=1 ", "slurm", "SLURM_CPUS_PER_TASK"}}) {
    if (w.prefix.rfind("taskset", 0) == 0 && RunCmd("taskset -c 0 true").code != 0) {
      ADD_FAILURE() << "taskset is missing (util-linux)";
      continue;
    }
    const auto r = RunCmd("env -u SLURM_CPUS_PER_TASK " + w.prefix + run + (dir / w.out).string());
    ASSERT_EQ(r.code, 0) << r.output;
    const CsvTable t = ReadCsv((dir / w.out / "results.csv").string());
    ASSERT_EQ(t.rows.size(), 1u);
    EXPECT_EQ(t.Cell(0, "threads"), "1") << w.prefix;
    const std::string prov = testing::ReadFile(dir / w.out / "provenance.yaml");
    EXPECT_NE(prov.find("threads_per_case: 1"), std::string::npos) << prov;
    EXPECT_NE(prov.find("cpus_from: " + w.from), std::string::npos) << prov;
  }
}

TEST(ShardCliTest, ADirectoryFromBeforeShardingIsStillReadAndResumed) {
  const auto dir = testing::TempDir("shards_legacy");
  testing::WriteFile(dir / "e.yaml",
                     Yaml("[0, 0.01, 0.02]", "tables:\n  - {name: t, metrics: [out_faces], rows: sleep_s}\n"));
  const std::string cmd = Arcs() + " run " + (dir / "e.yaml").string() + " --out " + (dir / "out").string();
  ASSERT_EQ(RunCmd(cmd).code, 0);
  const std::string before = testing::ReadFile(dir / "out" / "tables" / "t.csv");
  // What an older arcs left: results.csv, config and provenance, nothing else.
  fs::remove(dir / "out" / "experiment.id");
  fs::remove_all(dir / "out" / "locks");
  fs::remove_all(dir / "out" / "tables");
  const auto table = RunCmd(Arcs() + " table " + (dir / "out").string());
  ASSERT_EQ(table.code, 0) << table.output;
  EXPECT_EQ(testing::ReadFile(dir / "out" / "tables" / "t.csv"), before);
  const auto r = RunCmd(cmd);
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("3 skipped"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace arcs
