#include "orchestration/runner.h"

#include "orchestration/csv.h"
#include "orchestration/provenance.h"
#include "orchestration/schedule.h"
#include "orchestration/tables.h"
#include "orchestration/version.h"
#include "framework/util/cpus.h"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <set>

namespace fs = std::filesystem;

namespace arcs {

namespace {

std::string Clock(double s) {
  if (!(s >= 0) || s > 1e7) return "--:--:--";
  const long t = static_cast<long>(s + 0.5);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%02ld:%02ld:%02ld", t / 3600, (t / 60) % 60, t % 60);
  return buf;
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

// The cases a resumed run skips: those any results file of `out` records
// as ok, or as failed unless `retry_failed`.
std::set<std::string> CasesToSkip(const std::string& out, bool retry_failed) {
  std::set<std::string> done;
  if (ResultsFiles(out).empty()) return done;
  const CsvTable t = ReadResultsDir(out);
  const int id = t.Column("case_id"), st = t.Column("status");
  for (size_t r = 0; id >= 0 && r < t.rows.size(); ++r) {
    const std::string status = st >= 0 ? t.rows[r][st] : "";
    if (status == "ok" || (status == "failed" && !retry_failed)) done.insert(t.rows[r][id]);
  }
  return done;
}

// The progress line: "[n/total] pct | elapsed | ETA | current" (redrawn in
// place on a terminal, one line each otherwise).
void PrintProgress(int n, int total, int finished, int todo, double elapsed, bool tty, const std::string& current) {
  const double eta = finished > 0 ? elapsed / finished * (static_cast<double>(todo) - finished) : -1;
  char buf[512];
  std::snprintf(buf, sizeof buf, "[%d/%d] %5.1f%% | elapsed %s | ETA %s | %s", n, total,
                total ? 100.0 * n / total : 100.0, Clock(elapsed).c_str(), Clock(eta).c_str(), current.c_str());
  std::string line = buf;
  if (tty) {
    if (line.size() > 150) line = line.substr(0, 147) + "...";
    std::fprintf(stderr, "\r\033[K%s", line.c_str());
  } else {
    std::fprintf(stderr, "%s\n", line.c_str());
  }
  std::fflush(stderr);
}

// A case's log: appended to <out>/logs/<case id>.log, one timestamped line a message.
Context::LogFn CaseLog(const std::string& out, const Case& c) {
  auto path = std::make_shared<std::string>((fs::path(out) / "logs" / (c.id + ".log")).string());
  return Context::LogFn([path](LogLevel lvl, const std::string& msg) {
    static const char* names[] = {"debug", "info", "warning", "error"};
    if (FILE* f = std::fopen(path->c_str(), "a")) {
      std::fprintf(f, "%s [%s] %s\n", LocalTimeNow().c_str(), names[static_cast<int>(lvl)], msg.c_str());
      std::fclose(f);
    }
  });
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
  const std::set<std::string> done = CasesToSkip(out, options.retry_failed);
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
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  auto progress = [&](const std::string& current) {
    if (options.progress)
      PrintProgress(summary.skipped + finished, summary.total, finished, static_cast<int>(todo.size()), elapsed(), tty,
                    current);
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
  progress(todo.empty() ? "nothing to do" : "starting");
  ScheduleOptions so;
  so.jobs = jobs;
  so.isolate = options.isolate;
  so.case_timeout_s = exp.case_timeout_s;
  so.tmp_dir = tmp_dir.string();
  ScheduleHooks hooks;
  hooks.execute = [&](const Case& c) { return ExecuteCase(c, registry, threads, CaseLog(out, c), outputs_dir); };
  hooks.started = [&](const Case& c) { progress("running: " + c.Label()); };
  hooks.finished = record;
  summary.interrupted = RunSchedule(todo, so, hooks);
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
