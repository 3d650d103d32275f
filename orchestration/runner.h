// Running an experiment: cases in isolated worker processes (`jobs` at a
// time, each killed after case_timeout_s), results rows appended as each
// case ends, resume, shards, provenance, progress. One case itself runs in
// case_exec.h.
#pragma once

#include "orchestration/case_exec.h"
#include "orchestration/expand.h"
#include "orchestration/results_dir.h"

#include <string>
#include <vector>

namespace arcs {

struct RunOptions {
  std::string out_dir;          // results directory (created)
  int jobs = 1;                 // cases run at once
  int threads = 0;              // threads per case (0 = cores / jobs, at least 1)
  bool isolate = true;          // each case in a forked worker process
  bool retry_failed = false;    // re-run cases recorded as failed
  bool save_outputs = false;    // also when the experiment says save_outputs: write outputs/ (ExecuteCase)
  bool progress = true;         // progress line on stderr
  Shard shard;                  // the part of the cases this run does (default: all; see ShardCases)
  std::vector<std::string> command_line;  // for provenance
};

struct RunSummary {
  int total = 0, skipped = 0, ok = 0, failed = 0;
  bool interrupted = false;
};

// Expands and runs the experiment (options.shard's part of it); writes
// results.csv (results.<I>-of-<N>.csv for a shard), experiment.id,
// config.resolved.yaml, provenance.yaml (appended), logs/ into out_dir (see
// results_dir.h). Refuses (Error) another experiment's directory and a shard
// another runner holds; the table specs are checked against the results'
// columns before any case runs.
RunSummary RunExperiment(const Experiment& exp, const Registry& registry, const RunOptions& options);

// The experiment's cases (ExpandCases) after checking its table specs
// against the columns the results will have (ValidateTables): what a run
// would do, found wrong before anything runs.
std::vector<Case> PlanCases(const Experiment& exp, const Registry& registry);

// `arcs run --dry-run`: prints the cases of options.shard (id, dataset, item,
// input, method, swept values; "done" for those out_dir already has) and
// their count to stdout; runs nothing, writes nothing. Returns the count.
int ListCases(const Experiment& exp, const Registry& registry, const RunOptions& options);

// Default results directory for an experiment: results/<name>.
std::string DefaultOutDir(const Experiment& exp);

}  // namespace arcs
