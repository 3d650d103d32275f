// One results directory, many writers (orchestration/results_dir.h),
// and the checks made before any case runs: shards, torn tails, the union
// readers see, locks, identity, table specs, duplicate sweeps, the case cap.
#include "orchestration/results_dir.h"
#include "orchestration/runner.h"
#include "orchestration/tables.h"
#include "framework/util/cpus.h"
#include "stages/builtin.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <sched.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <map>
#include <set>

namespace arcs {
namespace {

namespace fs = std::filesystem;

std::string Slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

class ResultsDirTest : public ::testing::Test {
 protected:
  void SetUp() override {
    RegisterBuiltinStages(registry_);
    dir_ = testing::TempDir(std::string("results_dir_") +
                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
  }
  Experiment Load(const std::string& yaml, const std::vector<std::string>& sets = {}) {
    const std::string path = (dir_ / "exp.yaml").string();
    std::ofstream(path) << yaml;
    return LoadExperiment(path, sets, registry_);
  }
  Registry registry_;
  fs::path dir_;
};

// 4 shapes x n in {6, 8, 10, 12, 14} x 2 methods = 40 cases, cheap to expand.
const char* kSweep = R"(name: sweep
datasets: [{name: b, shapes: [sphere, torus, knot, two_tori]}]
inputs:
  - name: grid
    pipeline: [{stage: sdf_grid, params: {n: [6, 8, 10, 12, 14]}}]
methods:
  - {name: MC, pipeline: [marching_cubes]}
  - {name: MC2, pipeline: [{stage: marching_cubes, params: {level: 0.01}}]}
metrics: [mesh_size]
tables:
  - {name: t, metrics: [out_faces], rows: n, columns: method, groups: [{name: all}, {name: g0, where: "ref_genus == 0"}]}
)";

TEST_F(ResultsDirTest, ShardsPartitionTheCasesExactlyAndStably) {
  const Experiment exp = Load(kSweep);
  const std::vector<Case> cases = ExpandCases(exp, registry_);
  ASSERT_EQ(cases.size(), 40u);
  for (int n : {1, 2, 3, 7, 40}) {
    std::map<std::string, int> owner;
    size_t smallest = cases.size(), largest = 0;
    for (int i = 0; i < n; ++i) {
      const auto mine = ShardCases(cases, Shard{i, n, "--shard"});
      smallest = std::min(smallest, mine.size());
      largest = std::max(largest, mine.size());
      for (const Case* c : mine) EXPECT_TRUE(owner.emplace(c->id, i).second) << c->id << " in two shards of " << n;
    }
    EXPECT_EQ(owner.size(), cases.size()) << "shards of " << n << " cover every case";
    EXPECT_LE(largest - smallest, 1u) << "balanced counts at N=" << n;
  }
  // Cost-aware: with 4 shards, each gets 2 of the 8 most expensive (n = 14) cases.
  for (int i = 0; i < 4; ++i) {
    int big = 0;
    for (const Case* c : ShardCases(cases, Shard{i, 4, "--shard"}))
      for (const auto& [k, v] : c->params) big += k == "sdf_grid.n" && v == "14";
    EXPECT_EQ(big, 2) << "shard " << i;
  }
  // Stable: the order of the shapes in the file does not change a shard's content.
  std::string reordered = kSweep;
  reordered.replace(reordered.find("[sphere, torus, knot, two_tori]"), 31, "[two_tori, knot, torus, sphere]");
  const std::vector<Case> cases2 = ExpandCases(Load(reordered), registry_);
  for (int i = 0; i < 3; ++i) {
    std::set<std::string> a, b;
    for (const Case* c : ShardCases(cases, Shard{i, 3, "--shard"})) a.insert(c->id);
    for (const Case* c : ShardCases(cases2, Shard{i, 3, "--shard"})) b.insert(c->id);
    EXPECT_EQ(a, b) << "shard " << i;
  }
  EXPECT_EQ(ExperimentIdentity(cases), ExperimentIdentity(cases2));
  EXPECT_NE(ExperimentIdentity(cases), ExperimentIdentity(ExpandCases(Load(kSweep, {"seed=2"}), registry_)));
}

TEST_F(ResultsDirTest, ShardTextAndSlurmEnvironment) {
  const Shard s = ParseShard("2/3");
  EXPECT_EQ(s.index, 2);
  EXPECT_EQ(s.count, 3);
  for (const char* bad : {"3/3", "1", "-1/3", "a/b", "1/0", "/3", "1/"}) EXPECT_THROW(ParseShard(bad), Error) << bad;
  unsetenv("SLURM_ARRAY_TASK_ID");
  EXPECT_FALSE(ShardFromEnvironment().sharded());
  setenv("SLURM_ARRAY_TASK_ID", "5", 1);
  setenv("SLURM_ARRAY_TASK_MIN", "4", 1);
  setenv("SLURM_ARRAY_TASK_COUNT", "3", 1);
  const Shard e = ShardFromEnvironment();
  EXPECT_EQ(e.index, 1);
  EXPECT_EQ(e.count, 3);
  EXPECT_EQ(e.source, "SLURM_ARRAY_TASK_ID");
  setenv("SLURM_ARRAY_TASK_ID", "9", 1);
  EXPECT_THROW(ShardFromEnvironment(), Error);
  unsetenv("SLURM_ARRAY_TASK_ID");
  unsetenv("SLURM_ARRAY_TASK_MIN");
  unsetenv("SLURM_ARRAY_TASK_COUNT");
  EXPECT_EQ(ResultsFileName(Shard{}), "results.csv");
  EXPECT_EQ(ResultsFileName(Shard{1, 3, "--shard"}), "results.1-of-3.csv");
}

TEST_F(ResultsDirTest, TornTailIsCutToTheLastCompleteRow) {
  const std::string whole = "case_id,status,error\na,ok,\nb,failed,\"two\nlines, and a comma\"\nc,ok,\n";
  EXPECT_EQ(CompleteCsvPrefix(whole), whole.size());
  // Cut at every byte of the last two rows: what is kept is always whole rows.
  const size_t b_row = whole.find("b,failed");
  for (size_t cut = b_row; cut < whole.size(); ++cut) {
    const fs::path p = dir_ / "r.csv";
    testing::WriteFile(p, whole.substr(0, cut));
    RepairTornTail(p.string());
    const std::string kept = Slurp(p);
    const CsvTable t = ReadCsv(p.string());  // parses: no unterminated quote, no short row
    const size_t c_row = whole.find("c,ok");
    EXPECT_EQ(t.rows.size(), cut < c_row ? 1u : 2u) << "cut at " << cut;
    EXPECT_EQ(kept, whole.substr(0, cut < c_row ? b_row : c_row)) << "cut at " << cut;
  }
  // A whole file is left alone.
  testing::WriteFile(dir_ / "w.csv", whole);
  EXPECT_EQ(RepairTornTail((dir_ / "w.csv").string()), 0u);
  EXPECT_EQ(Slurp(dir_ / "w.csv"), whole);
}

TEST_F(ResultsDirTest, ReadersSeeTheUnionOfEveryShardOnce) {
  testing::WriteFile(dir_ / "results.csv", "case_id,status,x\na,ok,1\nb,failed,\n");
  testing::WriteFile(dir_ / "results.0-of-2.csv", "case_id,status,x,y\nb,ok,2,7\nc,ok,3,8\n");
  testing::WriteFile(dir_ / "results.1-of-2.csv", "case_id,status,x\nd,ok,4\ne,ok,\"5");  // being written
  testing::WriteFile(dir_ / "results.old.csv", "case_id,status\nz,ok\n");  // not a results file of ours
  testing::WriteFile(dir_ / "experiment.id", "id: 0\nname: t\ncases: 6\n");
  std::vector<std::string> warnings;
  const CsvTable t = ReadResultsDir(dir_.string(), &warnings);
  ASSERT_EQ(t.header, (std::vector<std::string>{"case_id", "status", "x", "y"}));
  std::map<std::string, std::string> x;
  for (size_t r = 0; r < t.rows.size(); ++r) x[t.Cell(r, "case_id") + ":" + t.Cell(r, "status")] = t.Cell(r, "x");
  EXPECT_EQ(x, (std::map<std::string, std::string>{{"a:ok", "1"}, {"b:ok", "2"}, {"c:ok", "3"}, {"d:ok", "4"}}));
  std::string all;
  for (const auto& w : warnings) all += w + "\n";
  EXPECT_NE(all.find("results.1-of-2.csv"), std::string::npos) << all;
  EXPECT_NE(all.find("4 of 6 cases"), std::string::npos) << all;
  EXPECT_EQ(Slurp(dir_ / "results.1-of-2.csv").back(), '5') << "a reader does not change a file";
  EXPECT_THROW(ReadResultsDir((dir_ / "nothing").string()), Error);
}

// A table run in parts (other sessions, grids, methods): the union of results
// directories and kept results files, one row per case id, an ok row over a
// failed one; a source that is neither is an error naming it.
TEST_F(ResultsDirTest, PartsOfARunMergeIntoOneTable) {
  const fs::path a = dir_ / "a", b = dir_ / "b";
  fs::create_directories(a);
  fs::create_directories(b);
  testing::WriteFile(a / "results.csv", "case_id,status,method,n,x\np,ok,MC,10,1\nq,failed,RFTA,10,\n");
  testing::WriteFile(b / "results.0-of-2.csv", "case_id,status,method,n,x\nq,ok,RFTA,10,2\n");
  testing::WriteFile(dir_ / "kept.csv", "case_id,status,method,n,x,host\nr,ok,RFTA,20,3,h\np,ok,MC,10,1,h\n");
  const CsvTable t = ReadResults({a.string(), b.string(), (dir_ / "kept.csv").string()});
  ASSERT_EQ(t.rows.size(), 3u);
  std::map<std::string, std::string> x;
  for (size_t r = 0; r < t.rows.size(); ++r) x[t.Cell(r, "case_id") + ":" + t.Cell(r, "status")] = t.Cell(r, "x");
  EXPECT_EQ(x, (std::map<std::string, std::string>{{"p:ok", "1"}, {"q:ok", "2"}, {"r:ok", "3"}}));
  EXPECT_NE(std::find(t.header.begin(), t.header.end(), "host"), t.header.end());
  // Tables over the union: n = 10 has MC and RFTA, n = 20 RFTA only.
  TableSpec spec;
  spec.name = "t";
  spec.metrics = {"x"};
  spec.rows = "n";
  spec.columns = "method";
  std::vector<std::string> warnings;
  const auto tables = BuildTables({spec}, t, &warnings);
  ASSERT_EQ(tables.size(), 1u);
  std::string cells;
  for (const auto& row : tables[0].cells)
    for (const auto& c : row) cells += c + "|";
  EXPECT_EQ(cells, "10|1|2|20|–|3|") << "rows n = 10, 20; columns MC, RFTA";
  try {
    ReadResults({a.string(), (dir_ / "missing").string()});
    FAIL() << "a missing source must be an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("missing"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ReadResults({}), Error);
}

TEST_F(ResultsDirTest, ALockIsHeldUntilItsHolderDies) {
  const std::string path = (dir_ / "x.lock").string();
  int ready[2], go[2];
  ASSERT_EQ(pipe(ready), 0);
  ASSERT_EQ(pipe(go), 0);
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    FileLock l;
    std::string h;
    const char ok = l.TryLock(path, "the child", &h) ? 'y' : 'n';
    (void)!write(ready[1], &ok, 1);
    char c;
    (void)!read(go[0], &c, 1);
    _exit(0);
  }
  char ok = 0;
  ASSERT_EQ(read(ready[0], &ok, 1), 1);
  ASSERT_EQ(ok, 'y');
  FileLock mine;
  std::string holder;
  EXPECT_FALSE(mine.TryLock(path, "the parent", &holder));
  EXPECT_NE(holder.find("pid " + std::to_string(pid)), std::string::npos) << holder;
  EXPECT_NE(holder.find("the child"), std::string::npos) << holder;
  kill(pid, SIGKILL);  // no clean-up: the kernel releases the lock
  waitpid(pid, nullptr, 0);
  EXPECT_TRUE(mine.TryLock(path, "the parent", &holder));
}

TEST_F(ResultsDirTest, AnotherExperimentsDirectoryIsRefused) {
  const Experiment a = Load(kSweep);
  const auto ca = ExpandCases(a, registry_);
  const std::string out = (dir_ / "out").string();
  ClaimResultsDir(out, a, ca, "config: a\n", "run: 1\n");
  ClaimResultsDir(out, a, ca, "config: a\n", "run: 2\n");  // the same experiment again: fine
  const std::string prov = Slurp(fs::path(out) / "provenance.yaml");
  EXPECT_NE(prov.find("run: 1"), std::string::npos);
  EXPECT_NE(prov.find("run: 2"), std::string::npos) << "provenance is appended, never overwritten";
  const Experiment b = Load(kSweep, {"seed=7"});
  try {
    ClaimResultsDir(out, b, ExpandCases(b, registry_), "config: b\n", "run: 3\n");
    FAIL() << "another experiment was let in";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("another experiment"), std::string::npos) << e.what();
  }
  EXPECT_EQ(Slurp(fs::path(out) / "config.resolved.yaml"), "config: a\n");
  // A directory from before experiment.id: accepted when its rows are our cases.
  const std::string legacy = (dir_ / "legacy").string();
  fs::create_directories(legacy);
  testing::WriteFile(fs::path(legacy) / "results.csv", "case_id,status\n" + ca[0].id + ",ok\n");
  EXPECT_THROW(ClaimResultsDir(legacy, b, ExpandCases(b, registry_), "c\n", "p\n"), Error);
  EXPECT_NO_THROW(ClaimResultsDir(legacy, a, ca, "c\n", "p\n"));
}

TEST_F(ResultsDirTest, TableMistakesAreFoundBeforeAnyCaseRuns) {
  auto expect = [&](const std::string& from, const std::string& to, const std::string& piece) {
    std::string y = kSweep;
    y.replace(y.find(from), from.size(), to);
    const Experiment e = Load(y);
    try {
      PlanCases(e, registry_);
      ADD_FAILURE() << "accepted: " << to;
    } catch (const Error& err) {
      EXPECT_NE(std::string(err.what()).find(piece), std::string::npos) << err.what();
    }
  };
  EXPECT_NO_THROW(PlanCases(Load(kSweep), registry_));
  expect("rows: n", "rows: nn", "tables[0].rows: rows column 'nn'");
  expect("where: \"ref_genus == 0\"", "where: \"ref_genu == 0\"", "tables[0].groups[1].where");
  expect("where: \"ref_genus == 0\"", "where: \"ref_genus = 0\"", "expected 'column OP value'");
  expect("name: t,", "name: ../../x,", "contains '..'");
  expect("name: t,", "name: a/b,", "path separator");
  expect("{name: g0,", "{name: ../g0,", "groups[1].name");
  // The writer refuses such a name too (arcs table with a hand-edited config).
  BuiltTable bad;
  bad.name = "../escape";
  bad.header = {"n"};
  EXPECT_THROW(WriteTables({bad}, (dir_ / "tables").string()), Error);
  EXPECT_FALSE(fs::exists(dir_ / "escape.md"));
}

TEST_F(ResultsDirTest, DuplicateSweepValuesAndCasesAreRefused) {
  std::string y = kSweep;
  y.replace(y.find("[6, 8, 10, 12, 14]"), 18, "[6, 8, 10, 8]");
  try {
    ExpandCases(Load(y), registry_);
    FAIL() << "a duplicate sweep value was accepted";
  } catch (const ExperimentError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("exp.yaml:"), std::string::npos) << m;
    EXPECT_NE(m.find("sdf_grid.params.n: sweep value 8 is listed twice"), std::string::npos) << m;
  }
  std::string twice = kSweep;
  twice.replace(twice.find("[sphere, torus, knot, two_tori]"), 31, "[sphere, torus, sphere]");
  try {
    ExpandCases(Load(twice), registry_);
    FAIL() << "a shape listed twice was accepted";
  } catch (const ExperimentError& e) {
    EXPECT_NE(std::string(e.what()).find("appears twice"), std::string::npos) << e.what();
  }
}

TEST_F(ResultsDirTest, AHugeSweepIsAClearErrorNotAnOutOfMemory) {
  // 4 shapes x 300 n x 300 lo x (1 + 3) methods = 1.44e6 cases: counted, never expanded.
  std::string list = "[";
  for (int i = 0; i < 300; ++i) list += (i ? ", " : "") + std::to_string(6 + i);
  list += "]";
  std::string levels = "[";
  for (int i = 0; i < 300; ++i) levels += (i ? ", " : "") + std::to_string(-1.0 - i * 1e-3);
  levels += "]";
  std::string y = kSweep;
  y.replace(y.find("{n: [6, 8, 10, 12, 14]}"), 23, "{n: " + list + ", lo: " + levels + "}");
  y.replace(y.find("{level: 0.01}"), 13, "{level: " + levels.substr(0, 0) + "[0.01, 0.02, 0.03]}");
  const Experiment e = Load(y);
  try {
    ExpandCases(e, registry_);
    FAIL() << "expanded";
  } catch (const ExperimentError& err) {
    const std::string m = err.what();
    EXPECT_NE(m.find("more than the limit of 100000"), std::string::npos) << m;
    EXPECT_NE(m.find("ARCS_MAX_CASES"), std::string::npos) << m;
  }
  setenv("ARCS_MAX_CASES", "10", 1);
  EXPECT_THROW(ExpandCases(Load(kSweep), registry_), ExperimentError);  // 40 > 10
  unsetenv("ARCS_MAX_CASES");
  EXPECT_EQ(ExpandCases(Load(kSweep), registry_).size(), 40u);
}

TEST_F(ResultsDirTest, CpusComeFromTheAllocation) {
  // In a child (the test process keeps its mask): pinned to one CPU -> 1.
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    cpu_set_t one;
    CPU_ZERO(&one);
    cpu_set_t all;
    sched_getaffinity(0, sizeof all, &all);
    for (int c = 0; c < CPU_SETSIZE; ++c)
      if (CPU_ISSET(c, &all)) {
        CPU_SET(c, &one);
        break;
      }
    unsetenv("SLURM_CPUS_PER_TASK");
    if (sched_setaffinity(0, sizeof one, &one) != 0) _exit(3);
    const CpuAllocation a = AvailableCpus();
    if (a.cpus != 1 || a.source != "sched_getaffinity") _exit(4);
    setenv("SLURM_CPUS_PER_TASK", "4", 1);  // capped by the mask
    const CpuAllocation b = AvailableCpus();
    _exit(b.cpus == 1 && b.source == "SLURM_CPUS_PER_TASK" && b.slurm_cpus == 4 ? 0 : 5);
  }
  int st = 0;
  waitpid(pid, &st, 0);
  EXPECT_TRUE(WIFEXITED(st) && WEXITSTATUS(st) == 0) << "child status " << st;
  setenv("SLURM_CPUS_PER_TASK", "1", 1);
  EXPECT_EQ(AvailableCpus().cpus, 1);
  unsetenv("SLURM_CPUS_PER_TASK");
}

}  // namespace
}  // namespace arcs
