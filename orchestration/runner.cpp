#include "orchestration/runner.h"

#include "orchestration/csv.h"
#include "orchestration/tables.h"
#include "orchestration/version.h"
#include "framework/util/cpus.h"
#include "registry/plugin.h"
#include "registry/plugin_api.h"

#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <signal.h>
#include <cerrno>
#include <csignal>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <thread>

namespace fs = std::filesystem;

namespace arcs {

namespace {

volatile std::sig_atomic_t g_interrupted = 0;
void OnSignal(int) { g_interrupted = 1; }

std::string Escape(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '\\') o += "\\\\";
    else if (c == '\n') o += "\\n";
    else if (c == '\t') o += "\\t";
    else o += c;
  }
  return o;
}

std::string Unescape(const std::string& s) {
  std::string o;
  for (size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '\\' && i + 1 < s.size()) {
      const char n = s[++i];
      o += n == 'n' ? '\n' : n == 't' ? '\t' : n;
    } else {
      o += s[i];
    }
  }
  return o;
}

void WriteRowFile(const std::string& path, const Row& row) {
  const std::string tmp = path + ".part";
  {
    std::ofstream out(tmp, std::ios::trunc);
    for (const auto& [k, v] : row) out << Escape(k) << '\t' << Escape(v) << '\n';
  }
  fs::rename(tmp, path);
}

bool ReadRowFile(const std::string& path, Row* row) {
  std::ifstream in(path);
  if (!in) return false;
  std::string line;
  while (std::getline(in, line)) {
    const size_t tab = line.find('\t');
    if (tab == std::string::npos) continue;
    row->emplace_back(Unescape(line.substr(0, tab)), Unescape(line.substr(tab + 1)));
  }
  return !row->empty();
}

std::string Clock(double s) {
  if (!(s >= 0) || s > 1e7) return "--:--:--";
  const long t = static_cast<long>(s + 0.5);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%02ld:%02ld:%02ld", t / 3600, (t / 60) % 60, t % 60);
  return buf;
}

std::string Now() {
  std::time_t t = std::time(nullptr);
  char buf[64];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%S%z", std::localtime(&t));
  return buf;
}

std::string Shell(const std::string& cmd) {
  std::string out;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return out;
  char buf[256];
  while (std::fgets(buf, sizeof buf, p)) out += buf;
  pclose(p);
  while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
  return out;
}

std::string Hostname() {
  char buf[256] = {0};
  gethostname(buf, sizeof buf - 1);
  return buf;
}

// The document after overrides, with every pipeline stage's parameters
// completed from the schema (swept ones keep their lists).
YAML::Node ResolvedConfig(const Experiment& exp, const Registry& registry) {
  YAML::Node doc = YAML::Clone(exp.resolved);
  auto fill = [&](YAML::Node pipelines, const std::vector<PipelineSpec>& specs) {
    for (size_t i = 0; i < specs.size() && i < pipelines.size(); ++i) {
      YAML::Node pl = pipelines[i]["pipeline"];
      for (size_t j = 0; j < specs[i].stages.size() && j < pl.size(); ++j) {
        const StageEntry& e = specs[i].stages[j];
        YAML::Node entry;
        entry["stage"] = e.stage;
        YAML::Node params(YAML::NodeType::Map);
        for (const auto& ps : registry.Get(e.stage).params.specs()) {
          auto it = std::find_if(e.values.begin(), e.values.end(), [&](const auto& kv) { return kv.first == ps.name; });
          if (it == e.values.end()) {
            params[ps.name] = FormatParamValue(ps.default_value);
          } else if (it->second.size() == 1) {
            params[ps.name] = FormatParamValue(it->second.front());
          } else {
            YAML::Node list(YAML::NodeType::Sequence);
            for (const auto& v : it->second) list.push_back(FormatParamValue(v));
            params[ps.name] = list;
          }
        }
        entry["params"] = params;
        pl[j] = entry;
      }
      pipelines[i]["name"] = specs[i].name;
    }
  };
  if (doc["inputs"]) fill(doc["inputs"], exp.inputs);
  if (doc["methods"]) fill(doc["methods"], exp.methods);
  doc["seed"] = exp.seed;
  // Paths made absolute so `arcs table DIR` works from anywhere.
  for (size_t i = 0; i < exp.datasets.size() && doc["datasets"] && i < doc["datasets"].size(); ++i) {
    YAML::Node files(YAML::NodeType::Sequence), shapes(YAML::NodeType::Sequence);
    for (const auto& f : exp.datasets[i].files) {
      if (f.rfind("shape:", 0) == 0) shapes.push_back(f.substr(6));
      else files.push_back(fs::absolute(f).lexically_normal().string());
    }
    YAML::Node d = doc["datasets"][i];
    d.remove("files");
    d.remove("shapes");
    if (files.size()) d["files"] = files;
    if (shapes.size()) d["shapes"] = shapes;
  }
  for (size_t i = 0; i < exp.tables.size() && doc["tables"] && i < doc["tables"].size(); ++i) {
    YAML::Node r = doc["tables"][i]["reference"];
    if (!r) continue;
    const auto& refs = exp.tables[i].references;
    if (r.IsSequence()) {
      for (size_t k = 0; k < r.size() && k < refs.size(); ++k) r[k]["file"] = fs::absolute(refs[k].file).string();
    } else if (!refs.empty()) {
      r["file"] = fs::absolute(refs[0].file).string();
    }
  }
  return doc;
}

std::string ProvenanceText(const Experiment& exp, const RunOptions& o, int threads, const CpuAllocation& cpu,
                           const std::string& experiment_id) {
  YAML::Emitter e;
  e << YAML::BeginMap;
  e << YAML::Key << "arcs_version" << YAML::Value << "0.1.0";
  e << YAML::Key << "plugin_api_version" << YAML::Value << ARCS_PLUGIN_API_VERSION;
  e << YAML::Key << "git_revision_at_build" << YAML::Value << GitRevision();
  const std::string rev = Shell(std::string("git -C '") + SourceDir() + "' rev-parse HEAD 2>/dev/null");
  const std::string dirty = Shell(std::string("git -C '") + SourceDir() + "' status --porcelain 2>/dev/null | head -1");
  e << YAML::Key << "git_revision_now" << YAML::Value << (rev.empty() ? "unknown" : rev);
  e << YAML::Key << "git_dirty" << YAML::Value << !dirty.empty();
  e << YAML::Key << "build_type" << YAML::Value << BuildType();
  e << YAML::Key << "host" << YAML::Value << Hostname();
  e << YAML::Key << "cores" << YAML::Value << std::thread::hardware_concurrency();
  e << YAML::Key << "cpus" << YAML::Value << cpu.cpus;
  e << YAML::Key << "cpus_from" << YAML::Value << cpu.source;
  e << YAML::Key << "affinity_cpus" << YAML::Value << cpu.affinity_cpus;
  if (cpu.slurm_cpus > 0) e << YAML::Key << "slurm_cpus_per_task" << YAML::Value << cpu.slurm_cpus;
  for (const char* v : {"SLURM_JOB_ID", "SLURM_ARRAY_JOB_ID", "SLURM_ARRAY_TASK_ID", "SLURM_JOB_PARTITION"})
    if (const char* x = std::getenv(v)) e << YAML::Key << v << YAML::Value << x;
  e << YAML::Key << "pid" << YAML::Value << static_cast<long>(getpid());
  e << YAML::Key << "started" << YAML::Value << Now();
  e << YAML::Key << "experiment_id" << YAML::Value << experiment_id;
  e << YAML::Key << "shard" << YAML::Value << o.shard.Text();
  e << YAML::Key << "shard_from" << YAML::Value << (o.shard.source.empty() ? "none" : o.shard.source);
  e << YAML::Key << "experiment" << YAML::Value << fs::absolute(exp.file).string();
  e << YAML::Key << "seed" << YAML::Value << exp.seed;
  e << YAML::Key << "jobs" << YAML::Value << o.jobs;
  e << YAML::Key << "threads_per_case" << YAML::Value << threads;
  e << YAML::Key << "isolated_processes" << YAML::Value << o.isolate;
  std::string cmd;
  for (const auto& a : o.command_line) cmd += (cmd.empty() ? "" : " ") + a;
  e << YAML::Key << "command" << YAML::Value << cmd;
  e << YAML::Key << "plugins" << YAML::Value << YAML::BeginSeq;
  for (const auto& p : LoadedPlugins()) {
    e << YAML::BeginMap << YAML::Key << "path" << YAML::Value << p.path << YAML::Key << "name" << YAML::Value
      << p.name << YAML::Key << "version" << YAML::Value << p.version << YAML::Key << "stages" << YAML::Value
      << YAML::Flow << p.stages << YAML::EndMap;
  }
  e << YAML::EndSeq << YAML::EndMap;
  return std::string(e.c_str()) + "\n";
}

// The results columns a run of these cases writes, in order: identity,
// parameters, metrics, timings, where it ran.
std::vector<std::string> PlannedColumns(const Experiment& exp, const Registry& registry, const std::vector<Case>& cases) {
  std::vector<std::string> cols = {"case_id", "status", "error", "dataset", "item", "input", "method", "seed"};
  for (const auto& c : cases)
    for (const auto& [k, v] : c.params)
      if (std::find(cols.begin(), cols.end(), k) == cols.end()) cols.push_back(k);
  cols.insert(cols.end(), {"ref_faces", "ref_genus", "ref_closed", "input_samples"});
  for (const auto& m : exp.metrics)
    for (const auto& o : registry.Get(m.stage).outputs)
      if (std::find(cols.begin(), cols.end(), o) == cols.end()) cols.push_back(o);
  cols.insert(cols.end(), {"input_wall_s", "method_wall_s", "method_peak_rss_mb", "method_extra_rss_mb", "wall_s",
                           "peak_rss_mb"});
  return cols;
}

// What a table may name: the planned columns and every output any stage of
// the experiment declares.
std::vector<std::string> TableColumns(const Experiment& exp, const Registry& registry, std::vector<std::string> cols) {
  auto add = [&](const std::string& stage) {
    if (const StageInfo* info = registry.Find(stage))
      for (const auto& o : info->outputs)
        if (std::find(cols.begin(), cols.end(), o) == cols.end()) cols.push_back(o);
  };
  for (const auto* pls : {&exp.inputs, &exp.methods})
    for (const auto& p : *pls)
      for (const auto& e : p.stages) add(e.stage);
  cols.insert(cols.end(), {"threads", "shard", "host", "git_revision", "output_file", "output_points_file"});
  return cols;
}

// Removes the scratch directories of runners on this host that are gone
// (killed with -9); others' are left alone.
void RemoveStaleTmp(const fs::path& tmp_root, const std::string& host) {
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(tmp_root, ec)) {
    const std::string n = e.path().filename().string();
    const size_t dash = n.rfind('-');
    if (dash == std::string::npos || n.substr(0, dash) != host) continue;
    const long pid = std::strtol(n.c_str() + dash + 1, nullptr, 10);
    if (pid > 0 && kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH) fs::remove_all(e.path(), ec);
  }
}

}  // namespace

std::string DefaultOutDir(const Experiment& exp) {
  return (fs::path("results") / exp.name).string();
}

RunSummary RunExperiment(const Experiment& exp, const Registry& registry, const RunOptions& options) {
  RunSummary summary;
  const std::vector<Case> cases = PlanCases(exp, registry);  // table mistakes found before any case runs
  std::vector<std::string> cols = PlannedColumns(exp, registry, cases);
  const std::vector<const Case*> mine = ShardCases(cases, options.shard);
  summary.total = static_cast<int>(mine.size());
  const std::string out = options.out_dir.empty() ? DefaultOutDir(exp) : options.out_dir;
  const std::string host = Hostname();
  fs::create_directories(fs::path(out) / "locks");
  // One runner per results file: a second one on the same shard is refused.
  const std::string results_name = ResultsFileName(options.shard);
  FileLock shard_lock;
  {
    const std::string what = options.shard.sharded() ? "shard " + options.shard.Text() : "all cases (no --shard)";
    std::string holder;
    if (!shard_lock.TryLock((fs::path(out) / "locks" / (results_name + ".lock")).string(), "arcs run " + what, &holder))
      throw Error(out + ": " + what + " of this directory is already being run (" + holder +
                  "); wait for it to finish, or run another shard (--shard I/N)");
  }
  const CpuAllocation cpu = AvailableCpus();
  const int jobs = std::max(1, options.jobs);
  const int threads = options.threads > 0 ? options.threads : std::max(1, cpu.cpus / jobs);
  {
    YAML::Emitter e;
    e << ResolvedConfig(exp, registry);
    ClaimResultsDir(out, exp, cases, std::string(e.c_str()) + "\n",
                    ProvenanceText(exp, options, threads, cpu, ExperimentIdentity(cases)));
  }
  fs::create_directories(fs::path(out) / "logs");
  const fs::path tmp_dir = fs::path(out) / "tmp" / (host + "-" + std::to_string(getpid()));
  RemoveStaleTmp(fs::path(out) / "tmp", host);
  fs::create_directories(tmp_dir);
  const std::string outputs_dir =
      options.save_outputs || exp.save_outputs ? (fs::path(out) / "outputs").string() : std::string();
  if (!outputs_dir.empty()) fs::create_directories(outputs_dir);

  // This run's results file: a torn last row (disk full, power loss) is cut
  // off before anything is appended.
  const std::string results_path = (fs::path(out) / results_name).string();
  if (const auto dropped = RepairTornTail(results_path))
    std::fprintf(stderr, "warning: %s: its last row was incomplete (%ju bytes: a write cut short); removed, the case will run again\n",
                 results_path.c_str(), dropped);
  // Resume: cases recorded in any results file of the directory are skipped.
  std::set<std::string> done;
  if (!ResultsFiles(out).empty()) {
    const CsvTable t = ReadResultsDir(out);
    const int id = t.Column("case_id"), st = t.Column("status");
    for (size_t r = 0; r < t.rows.size(); ++r) {
      if (id < 0) break;
      const std::string status = st >= 0 ? t.rows[r][st] : "";
      if (status == "ok" || (status == "failed" && !options.retry_failed)) done.insert(t.rows[r][id]);
    }
  }
  ResultsCsv csv(results_path);
  // Column order: identity, parameters, metrics, timings, where it ran.
  cols.insert(cols.end(), {"threads", "shard", "host", "git_revision"});
  csv.EnsureColumns(cols);

  std::vector<const Case*> todo;
  for (const Case* c : mine) {
    if (done.count(c->id)) ++summary.skipped;
    else todo.push_back(c);
  }

  const auto start = std::chrono::steady_clock::now();
  const bool tty = options.progress && isatty(STDERR_FILENO);
  int finished = 0;
  std::map<pid_t, std::pair<const Case*, std::chrono::steady_clock::time_point>> running;
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  auto progress = [&](const std::string& current) {
    if (!options.progress) return;
    const int n = summary.skipped + finished;
    const double el = elapsed();
    const double eta = finished > 0 ? el / finished * (static_cast<double>(todo.size()) - finished) / 1.0 : -1;
    char buf[512];
    std::snprintf(buf, sizeof buf, "[%d/%d] %5.1f%% | elapsed %s | ETA %s | %s", n, summary.total,
                  summary.total ? 100.0 * n / summary.total : 100.0, Clock(el).c_str(), Clock(eta).c_str(),
                  current.c_str());
    std::string line = buf;
    if (tty) {
      if (line.size() > 150) line = line.substr(0, 147) + "...";
      std::fprintf(stderr, "\r\033[K%s", line.c_str());
    } else {
      std::fprintf(stderr, "%s\n", line.c_str());
    }
    std::fflush(stderr);
  };
  auto record = [&](const Case& c, Row row) {
    row.emplace_back("threads", std::to_string(threads));
    row.emplace_back("shard", options.shard.Text());
    row.emplace_back("host", host);
    row.emplace_back("git_revision", GitRevision());
    csv.Append(row);
    std::string status, error;
    for (const auto& [k, v] : row) {
      if (k == "status") status = v;
      if (k == "error") error = v;
    }
    if (status == "ok") ++summary.ok;
    else ++summary.failed;
    ++finished;
    if (status != "ok" && options.progress) {
      if (tty) std::fprintf(stderr, "\r\033[K");
      std::fprintf(stderr, "case %s (%s) failed: %s\n", c.id.c_str(), c.Label().c_str(), error.c_str());
    }
    progress(status + ": " + c.Label());
  };
  auto log_for = [&](const Case& c) {
    auto path = std::make_shared<std::string>((fs::path(out) / "logs" / (c.id + ".log")).string());
    return Context::LogFn([path](LogLevel lvl, const std::string& msg) {
      static const char* names[] = {"debug", "info", "warning", "error"};
      if (FILE* f = std::fopen(path->c_str(), "a")) {
        std::fprintf(f, "%s [%s] %s\n", Now().c_str(), names[static_cast<int>(lvl)], msg.c_str());
        std::fclose(f);
      }
    });
  };

  g_interrupted = 0;
  struct sigaction sa {}, old_int {}, old_term {};
  sa.sa_handler = OnSignal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, &old_int);
  sigaction(SIGTERM, &sa, &old_term);

  progress(todo.empty() ? "nothing to do" : "starting");
  if (!options.isolate) {
    for (const Case* c : todo) {
      if (g_interrupted) break;
      progress("running: " + c->Label());
      record(*c, ExecuteCase(*c, registry, threads, log_for(*c), outputs_dir));
    }
  } else {
    size_t next = 0;
    while ((next < todo.size() || !running.empty()) && !g_interrupted) {
      while (next < todo.size() && static_cast<int>(running.size()) < jobs && !g_interrupted) {
        const Case* c = todo[next++];
        std::fflush(nullptr);
        const pid_t parent = getpid();
        const pid_t pid = fork();
        if (pid < 0) {
          Row row = {{"case_id", c->id}, {"status", "failed"}, {"error", "fork failed: " + std::string(std::strerror(errno))}};
          record(*c, row);
          continue;
        }
        if (pid == 0) {
          prctl(PR_SET_PDEATHSIG, SIGKILL);  // a worker does not outlive its runner (kill -9)
          if (getppid() != parent) _exit(1);
          // The worker ends here whatever happens: an exception must not
          // unwind into the parent's code path (it would run the loop on).
          int rc = 0;
          try {
            signal(SIGINT, SIG_DFL);
            signal(SIGTERM, SIG_DFL);
            Row row = ExecuteCase(*c, registry, threads, log_for(*c), outputs_dir);
            WriteRowFile((tmp_dir / (c->id + ".row")).string(), row);
          } catch (const std::exception& e) {
            std::fprintf(stderr, "arcs: worker of case %s: %s\n", c->id.c_str(), e.what());
            rc = 3;
          } catch (...) {
            rc = 3;
          }
          std::fflush(nullptr);
          _exit(rc);
        }
        running[pid] = {c, std::chrono::steady_clock::now()};
        progress("running: " + c->Label());
      }
      int status = 0;
      struct rusage ru {};
      const pid_t pid = wait4(-1, &status, WNOHANG, &ru);
      if (pid > 0 && running.count(pid)) {
        const Case* c = running[pid].first;
        running.erase(pid);
        const std::string row_file = (tmp_dir / (c->id + ".row")).string();
        Row row;
        if (WIFEXITED(status) && WEXITSTATUS(status) == 0 && ReadRowFile(row_file, &row)) {
          // The kernel's figure for the whole worker process.
          for (auto& [k, v] : row)
            if (k == "peak_rss_mb") v = std::to_string(ru.ru_maxrss / 1024.0);
        } else if (g_interrupted) {
          break;
        } else {
          std::string why = WIFSIGNALED(status) ? "worker crashed: signal " + std::to_string(WTERMSIG(status)) + " (" +
                                                      strsignal(WTERMSIG(status)) + ")"
                                                : "worker exited with status " + std::to_string(WEXITSTATUS(status));
          if (WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL && exp.case_timeout_s > 0)
            why = "timed out after " + std::to_string(exp.case_timeout_s) + " s (or killed: out of memory?)";
          row = {{"case_id", c->id}, {"status", "failed"}, {"error", why}, {"dataset", c->dataset}, {"item", c->item},
                 {"input", c->input}, {"method", c->method}, {"seed", std::to_string(c->seed)}};
          for (const auto& p : c->params) row.push_back(p);
          row.emplace_back("peak_rss_mb", std::to_string(ru.ru_maxrss / 1024.0));
        }
        std::error_code ec;
        fs::remove(row_file, ec);
        record(*c, row);
        continue;
      }
      // Timeouts.
      if (exp.case_timeout_s > 0) {
        for (auto& [p, info] : running) {
          const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - info.second).count();
          if (t > exp.case_timeout_s) kill(p, SIGKILL);
        }
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    if (g_interrupted) {
      for (auto& [p, info] : running) kill(p, SIGTERM);
      for (auto& [p, info] : running) waitpid(p, nullptr, 0);
    }
  }
  sigaction(SIGINT, &old_int, nullptr);
  sigaction(SIGTERM, &old_term, nullptr);
  summary.interrupted = g_interrupted != 0;
  if (options.progress) {
    if (tty) std::fprintf(stderr, "\r\033[K");
    std::fprintf(stderr, "%s: %d cases, %d ok, %d failed, %d skipped (already done)%s in %s\n", exp.name.c_str(),
                 summary.total, summary.ok, summary.failed, summary.skipped,
                 summary.interrupted ? ", INTERRUPTED (re-run the same command to resume)" : "", Clock(elapsed()).c_str());
  }
  std::error_code ec;
  fs::remove_all(tmp_dir, ec);
  fs::remove(fs::path(out) / "tmp", ec);  // only when empty: other runners' scratch stays
  return summary;
}

std::vector<Case> PlanCases(const Experiment& exp, const Registry& registry) {
  std::vector<Case> cases = ExpandCases(exp, registry);
  ValidateTables(exp.tables, TableColumns(exp, registry, PlannedColumns(exp, registry, cases)), exp.file);
  return cases;
}

int ListCases(const Experiment& exp, const Registry& registry, const RunOptions& options) {
  const std::vector<Case> cases = PlanCases(exp, registry);
  const std::vector<const Case*> mine = ShardCases(cases, options.shard);
  const std::string out = options.out_dir.empty() ? DefaultOutDir(exp) : options.out_dir;
  std::set<std::string> done;
  if (fs::exists(out) && !ResultsFiles(out).empty()) {
    const CsvTable t = ReadResultsDir(out);
    const int id = t.Column("case_id");
    for (size_t r = 0; id >= 0 && r < t.rows.size(); ++r) done.insert(t.rows[r][id]);
  }
  std::printf("# %s: %zu cases%s (experiment id %s)\n", exp.name.c_str(), cases.size(),
              options.shard.sharded() ? (", shard " + options.shard.Text() + " has " + std::to_string(mine.size())).c_str() : "",
              ExperimentIdentity(cases).c_str());
  std::printf("# case_id\tdataset\titem\tinput\tmethod\tswept values\tstate\n");
  for (const Case* c : mine) {
    std::string swept;
    for (const auto& [k, v] : c->params)
      if (std::find(c->varying.begin(), c->varying.end(), k) != c->varying.end()) swept += (swept.empty() ? "" : " ") + k + "=" + v;
    std::printf("%s\t%s\t%s\t%s\t%s\t%s\t%s\n", c->id.c_str(), c->dataset.c_str(), c->item.c_str(), c->input.c_str(),
                c->method.c_str(), swept.empty() ? "-" : swept.c_str(), done.count(c->id) ? "done" : "todo");
  }
  std::printf("%zu cases\n", mine.size());
  return static_cast<int>(mine.size());
}

}  // namespace arcs
