// The quickstart on a real Slurm cluster: scripts/slurm_local.sh starts a
// single-node cluster on localhost (munge, slurmctld, slurmd), `arcs slurm
// --array 3 --submit` queues the array and the dependent table job, and the
// results must equal a single-process run's: the same case ids, statuses and
// metric values (timings aside), the same tables. Skips, saying why, where a
// cluster cannot start (not root, slurm-wlm/munge not installed, a daemon that
// does not come up). Stops only the daemons the script started, by pid.
//
// The metrics' sample counts are lowered (--set ...samples=20000) to keep the
// test to a couple of minutes on 2 busy cores; the cases are the quickstart's.
#include "orchestration/results_dir.h"
#include "tests/e2e/e2e_util.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <map>
#include <regex>
#include <thread>

namespace arcs {
namespace {

namespace fs = std::filesystem;
using testing::Arcs;
using testing::RunCmd;

bool PortFree(int port) {
  const int s = socket(AF_INET, SOCK_STREAM, 0);
  if (s < 0) return false;
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<uint16_t>(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  const bool ok = bind(s, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
  close(s);
  return ok;
}

std::string Script() { return std::string("'") + ARCS_SOURCE_DIR + "/scripts/slurm_local.sh'"; }

// Stops the cluster however the test ends.
struct Cluster {
  std::string dir;
  ~Cluster() {
    if (!dir.empty()) RunCmd(Script() + " stop '" + dir + "'");
  }
};

double Seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Columns that differ between runs by nature: timings, memory, where it ran.
bool Incidental(const std::string& c) {
  auto ends = [&](const char* s) {
    const std::string x = s;
    return c.size() >= x.size() && c.compare(c.size() - x.size(), x.size(), x) == 0;
  };
  return ends("_s") || ends("_mb") || c == "threads" || c == "shard" || c == "host" || c == "git_revision";
}

TEST(SlurmClusterTest, QuickstartAsAnArrayOfThreeEqualsOneProcess) {
  if (geteuid() != 0) GTEST_SKIP() << "needs root to start a local Slurm cluster (slurmd runs the jobs)";
  if (RunCmd("command -v slurmctld && command -v slurmd && command -v sbatch && command -v squeue && "
             "(command -v munged || test -x /usr/sbin/munged)").code != 0)
    GTEST_SKIP() << "slurm-wlm / munge are not installed (scripts/install_deps.sh installs them)";
  int port = 16817;
  while (port < 16900 && !(PortFree(port) && PortFree(port + 1))) port += 2;
  const fs::path root = testing::TempDir("slurm_cluster");
  Cluster cluster;
  const std::string cdir = (root / "cluster").string();
  const auto up = RunCmd("ARCS_SLURM_PORT=" + std::to_string(port) + " " + Script() + " start '" + cdir + "'");
  if (up.code != 0) GTEST_SKIP() << "the local Slurm cluster did not start (exit " << up.code << "): " << up.output;
  cluster.dir = cdir;
  setenv("SLURM_CONF", (fs::path(cdir) / "slurm.conf").c_str(), 1);

  const std::string exp = std::string(ARCS_SOURCE_DIR) + "/experiments/quickstart.yaml";
  const std::string sets = " --set metrics.chamfer.samples=20000";
  const fs::path single = root / "single", array = root / "array";

  const auto t_array = std::chrono::steady_clock::now();
  const auto sub = RunCmd(Arcs() + " slurm " + exp + " --array 3 --cpus 1 --out " + array.string() + sets + " --submit");
  ASSERT_EQ(sub.code, 0) << sub.output;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(sub.output, m, std::regex("array_job=(\\d+) table_job=(\\d+)"))) << sub.output;
  const std::string jobs = m[1].str() + "," + m[2].str();
  // Wait for both jobs to leave the queue.
  bool gone = false;
  while (Seconds(t_array) < 600) {
    const auto q = RunCmd("squeue -h -o '%i %T' -j " + jobs);
    if (q.code == 0 && q.output.find_first_not_of(" \n") == std::string::npos) {
      gone = true;
      break;
    }
    if (q.code != 0 && q.output.find("Invalid job id") != std::string::npos) {
      gone = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
  }
  const double array_wall = Seconds(t_array);
  ASSERT_TRUE(gone) << "the jobs did not finish within 600 s:\n" << RunCmd("squeue").output;

  const auto t_single = std::chrono::steady_clock::now();
  const auto one = RunCmd(Arcs() + " run " + exp + " --quiet --out " + single.string() + sets);
  ASSERT_EQ(one.code, 0) << one.output;
  const double single_wall = Seconds(t_single);
  std::printf("quickstart (samples 20000): array of 3 on the local cluster %.1f s (submit to done), "
              "one process %.1f s\n", array_wall, single_wall);

  // Each task wrote its own shard's file, on 1 CPU (SLURM_CPUS_PER_TASK); the
  // shards hold every case of the single run between them.
  const size_t total = ReadResultsDir(single.string()).rows.size();
  ASSERT_EQ(total, 16u) << "the quickstart: 4 shapes x 2 n x (MC, RFTA)";
  size_t in_shards = 0;
  for (int i = 0; i < 3; ++i) {
    const fs::path f = array / ("results." + std::to_string(i) + "-of-3.csv");
    ASSERT_TRUE(fs::exists(f)) << f << "\n" << RunCmd("cat " + (array / "slurm" / "logs").string() + "/*").output;
    const CsvTable t = ReadCsv(f.string());
    EXPECT_GE(t.rows.size(), total / 3) << f;
    EXPECT_LE(t.rows.size(), total / 3 + 1) << f;
    in_shards += t.rows.size();
    for (size_t r = 0; r < t.rows.size(); ++r) {
      EXPECT_EQ(t.Cell(r, "shard"), std::to_string(i) + "/3");
      EXPECT_EQ(t.Cell(r, "threads"), "1");
    }
  }
  EXPECT_EQ(in_shards, total);
  EXPECT_FALSE(fs::exists(array / "results.csv"));
  const std::string prov = testing::ReadFile(array / "provenance.yaml");
  EXPECT_NE(prov.find("cpus_from: SLURM_CPUS_PER_TASK"), std::string::npos) << prov;
  EXPECT_TRUE(std::regex_search(prov, std::regex("SLURM_ARRAY_JOB_ID: \"?" + m[1].str()))) << prov;

  // The same cases, statuses and values.
  const CsvTable a = ReadResultsDir(array.string()), s = ReadResultsDir(single.string());
  ASSERT_EQ(a.rows.size(), total);
  ASSERT_EQ(s.rows.size(), total);
  std::map<std::string, size_t> in_single;
  for (size_t r = 0; r < s.rows.size(); ++r) in_single[s.Cell(r, "case_id")] = r;
  int compared = 0;
  for (size_t r = 0; r < a.rows.size(); ++r) {
    const std::string id = a.Cell(r, "case_id");
    ASSERT_TRUE(in_single.count(id)) << "case " << id << " is not in the single run";
    EXPECT_EQ(a.Cell(r, "status"), "ok") << id << ": " << a.Cell(r, "error");
    for (const auto& col : s.header) {
      if (Incidental(col)) continue;
      EXPECT_EQ(a.Cell(r, col), s.Cell(in_single[id], col)) << "case " << id << ", column " << col;
      ++compared;
    }
  }
  EXPECT_GT(compared, 12 * 20);
  // The table job built the same tables.
  ASSERT_TRUE(fs::exists(array / "tables" / "tables.md"))
      << RunCmd("cat " + (array / "slurm" / "logs").string() + "/*tables.out").output;
  int tables = 0;
  for (const auto& e : fs::directory_iterator(single / "tables")) {
    const fs::path other = array / "tables" / e.path().filename();
    ASSERT_TRUE(fs::exists(other)) << other;
    EXPECT_EQ(testing::ReadFile(e.path()), testing::ReadFile(other)) << e.path().filename();
    ++tables;
  }
  EXPECT_GE(tables, 10);  // 3 groups x md/csv/tex + tables.md
}

}  // namespace
}  // namespace arcs
