// arcs slurm EXP.yaml --array N --out DIR [...] [--submit]: an experiment as
// a Slurm job array. Writes two sbatch scripts: the array (task I runs
// `arcs run EXP --shard I/N --out DIR`) and a table job (`arcs table DIR`)
// that --submit queues after the array (--dependency=afterany). The results
// directory takes many writers (orchestration/results_dir.h).
#include "app/cli.h"
#include "app/commands.h"
#include "orchestration/spec.h"
#include "orchestration/results_dir.h"
#include "orchestration/runner.h"
#include "registry/plugin.h"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace arcs {

namespace {

constexpr const char* kSlurmUsage = R"(arcs slurm EXP.yaml --array N --out DIR [options] [--submit]

Runs an experiment as a Slurm job array: N tasks, task I running shard I/N of
the cases (`arcs run EXP --shard I/N --out DIR`; a stable, cost-aware
partition: `arcs run EXP --dry-run --shard I/N` lists a task's cases), all
writing into the one results directory DIR (on a filesystem every node sees),
plus a table job that starts when the array has ended (afterany) and builds
DIR/tables/ from every shard's rows (`arcs table DIR`).

options:
  --array N           number of array tasks (shards); at most the number of cases
  --out DIR           results directory (default: results/<name>)
  --partition P       #SBATCH --partition
  --time T            #SBATCH --time of each array task (e.g. 04:00:00)
  --cpus C            #SBATCH --cpus-per-task (default 1); each task runs its cases
                      one at a time on C threads (arcs reads SLURM_CPUS_PER_TASK)
  --mem M             #SBATCH --mem of each task (e.g. 8G)
  --account A         #SBATCH --account
  --sbatch OPT        an extra #SBATCH line, repeatable (e.g. --sbatch --qos=long)
  --set path=value    experiment overrides, passed to every task (as `arcs run --set`)
  --plugin FILE       plugin, passed to every task
  --script FILE       where the array script goes (default DIR/slurm/<name>.sbatch);
                      the table job's script is written beside it (<stem>_tables.sbatch)
  --retry-failed      tasks re-run the cases recorded as failed (as `arcs run --retry-failed`)
  --submit            also submit: sbatch the array, then the table job after it

Resuming: every task skips the cases DIR already has, so after a timeout or a
failed node submit the same script again (all of it, or `sbatch --array=I`).
A second experiment into DIR is refused; two runners on one shard refuse too.

The paper's full table (docs/cluster.md has the whole recipe):
  arcs run experiments/rfta_table1.yaml --dry-run | tail -1      # how many cases
  arcs slurm experiments/rfta_table1.yaml --array 64 --cpus 2 --mem 8G \
      --time 08:00:00 --out /scratch/$USER/rfta_table1 --submit
  squeue -u $USER                                                # wait
  cat /scratch/$USER/rfta_table1/tables/tables.md
)";

[[noreturn]] void SlurmUsage(const std::string& msg) { cli::Usage(msg + "\nusage: " + kSlurmUsage); }

// Single-quoted for sh.
std::string Quote(const std::string& s) {
  std::string o = "'";
  for (char c : s) o += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return o + "'";
}

std::string SelfExe() {
  std::error_code ec;
  const fs::path p = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string("arcs") : p.string();
}

std::string Now() {
  std::time_t t = std::time(nullptr);
  char buf[64];
  std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M:%S %z", std::localtime(&t));
  return buf;
}

// Runs a command, returns its stdout (trimmed) and exit status.
int Capture(const std::string& cmd, std::string* out) {
  out->clear();
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return -1;
  char buf[512];
  while (std::fgets(buf, sizeof buf, p)) *out += buf;
  const int st = pclose(p);
  while (!out->empty() && (out->back() == '\n' || out->back() == '\r' || out->back() == ' ')) out->pop_back();
  return WIFEXITED(st) ? WEXITSTATUS(st) : 128;
}

void WriteScript(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  {
    std::ofstream out(path, std::ios::trunc);
    out << text;
    if (!out) throw Error(path.string() + ": cannot write the sbatch script");
  }
  fs::permissions(path, fs::perms::owner_exec | fs::perms::group_exec, fs::perm_options::add);
}

}  // namespace

int CmdSlurm(Registry& registry, int argc, char** argv) {
  for (int i = 2; i < argc; ++i)
    if (!std::strcmp(argv[i], "--help") || !std::strcmp(argv[i], "-h")) {
      std::printf("%s", kSlurmUsage);
      return 0;
    }
  const cli::Args a =
      cli::Parse(argc, argv, 2,
                 {"--array", "--out", "--partition", "--time", "--cpus", "--mem", "--account", "--sbatch", "--set",
                  "--plugin", "--script"},
                 {"--submit", "--retry-failed"});
  if (a.positional.size() != 1) SlurmUsage("slurm needs exactly one experiment file");
  if (!a.Has("--array")) SlurmUsage("slurm needs --array N (the number of array tasks)");
  int tasks = cli::ParseInt(a.Get("--array"), "--array");
  if (tasks < 1) SlurmUsage("--array must be >= 1");
  const int cpus = a.Has("--cpus") ? cli::ParseInt(a.Get("--cpus"), "--cpus") : 1;
  if (cpus < 1) SlurmUsage("--cpus must be >= 1");
  for (const auto& p : a.All("--plugin")) LoadPlugin(registry, p);

  // Everything a task would find wrong is found here, on the login node.
  const std::string exp_file = fs::absolute(a.positional[0]).lexically_normal().string();
  const Experiment exp = LoadExperiment(exp_file, a.All("--set"), registry);
  const std::vector<Case> cases = PlanCases(exp, registry);
  if (cases.empty()) throw Error(exp_file + ": the experiment has no cases");
  const std::string out = fs::absolute(a.Get("--out", DefaultOutDir(exp))).lexically_normal().string();
  CheckResultsDir(out, exp, cases);
  if (tasks > static_cast<int>(cases.size())) {
    std::fprintf(stderr, "note: %d tasks asked for %zu cases: using %zu tasks (one case each)\n", tasks, cases.size(),
                 cases.size());
    tasks = static_cast<int>(cases.size());
  }
  size_t largest = 0;
  for (int i = 0; i < tasks; ++i) largest = std::max(largest, ShardCases(cases, Shard{i, tasks, "--shard"}).size());

  const fs::path script = a.Has("--script") ? fs::absolute(a.Get("--script")) : fs::path(out) / "slurm" / (exp.name + ".sbatch");
  const fs::path tables_script = script.parent_path() / (script.stem().string() + "_tables.sbatch");
  const fs::path logs = fs::path(out) / "slurm" / "logs";
  fs::create_directories(logs);

  std::string passed;  // options every task gets
  for (const auto& s : a.All("--set")) passed += " --set " + Quote(s);
  for (const auto& p : a.All("--plugin")) passed += " --plugin " + Quote(fs::absolute(p).string());
  if (a.Has("--retry-failed")) passed += " --retry-failed";
  auto header = [&](const std::string& job, bool array) {
    std::string h = "#!/bin/bash\n";
    h += "# Written by `arcs slurm` on " + Now() + ": experiment '" + exp.name + "' (" + exp_file + "), " +
         std::to_string(cases.size()) + " cases in " + std::to_string(tasks) + " shards of at most " +
         std::to_string(largest) + ".\n";
    h += "#SBATCH --job-name=" + job + "\n";
    if (array) {
      h += "#SBATCH --array=0-" + std::to_string(tasks - 1) + "\n";
      h += "#SBATCH --cpus-per-task=" + std::to_string(cpus) + "\n";
      h += "#SBATCH --output=" + (logs / "%A_%a.out").string() + "\n";
      if (a.Has("--time")) h += "#SBATCH --time=" + a.Get("--time") + "\n";
      if (a.Has("--mem")) h += "#SBATCH --mem=" + a.Get("--mem") + "\n";
    } else {
      h += "#SBATCH --cpus-per-task=1\n";
      h += "#SBATCH --output=" + (logs / "%j_tables.out").string() + "\n";
      if (a.Has("--time")) h += "#SBATCH --time=00:30:00\n";
    }
    if (a.Has("--partition")) h += "#SBATCH --partition=" + a.Get("--partition") + "\n";
    if (a.Has("--account")) h += "#SBATCH --account=" + a.Get("--account") + "\n";
    for (const auto& o : a.All("--sbatch")) h += "#SBATCH " + o + "\n";
    return h + "set -euo pipefail\n";
  };
  WriteScript(script, header("arcs-" + exp.name, true) +
                          "# Task I runs shard I/" + std::to_string(tasks) +
                          "; finished cases are skipped, so resubmitting resumes.\n"
                          "exec " + Quote(SelfExe()) + " run " + Quote(exp_file) + " --out " + Quote(out) +
                          " --shard \"${SLURM_ARRAY_TASK_ID}/" + std::to_string(tasks) + "\"" + passed + "\n");
  WriteScript(tables_script, header("arcs-" + exp.name + "-tables", false) +
                                 "# The tables from every shard's rows (warns about cases still missing).\n"
                                 "exec " + Quote(SelfExe()) + " table " + Quote(out) + "\n");
  std::printf("wrote %s (array of %d tasks, %zu cases) and %s (the tables)\n", script.c_str(), tasks, cases.size(),
              tables_script.c_str());
  if (!a.Has("--submit")) {
    std::printf("submit with:\n  jid=$(sbatch --parsable %s)\n  sbatch --dependency=afterany:${jid%%%%;*} %s\n",
                Quote(script.string()).c_str(), Quote(tables_script.string()).c_str());
    return 0;
  }
  std::string jid, tid;
  if (Capture("sbatch --parsable " + Quote(script.string()) + " 2>&1", &jid) != 0 || jid.empty())
    throw Error("sbatch " + script.string() + " failed" + (jid.empty() ? "" : ": " + jid) +
                " (is this a Slurm login node? is sbatch on PATH?)");
  jid = jid.substr(0, jid.find(';'));  // "id;cluster" on multi-cluster sites
  if (Capture("sbatch --parsable --dependency=afterany:" + jid + " " + Quote(tables_script.string()) + " 2>&1", &tid) !=
          0 || tid.empty())
    throw Error("array job " + jid + " submitted, but the table job was not: " + tid + " (run `arcs table " + out +
                "` when the array is done)");
  tid = tid.substr(0, tid.find(';'));
  std::printf("submitted array job %s (%d tasks) and table job %s (after it)\n", jid.c_str(), tasks, tid.c_str());
  std::printf("array_job=%s table_job=%s\n", jid.c_str(), tid.c_str());
  return 0;
}

}  // namespace arcs
