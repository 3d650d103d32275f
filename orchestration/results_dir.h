// One results directory, many writers: per-shard results files, locks,
// the experiment's identity, torn-tail repair, and the union readers see.
//
// Layout of a results directory DIR:
//   results.csv              rows of an unsharded run (the only file before sharding existed)
//   results.<I>-of-<N>.csv   rows of shard I of N (`arcs run --shard I/N`, Slurm array task I)
//   experiment.id            the experiment's identity; another experiment is refused
//   config.resolved.yaml     the resolved experiment (what `arcs table DIR` reads)
//   provenance.yaml          one YAML document appended per run (never overwritten)
//   locks/                   flock(2) files: dir.lock (setup) and one per results file
//   logs/<case id>.log       each case's log; tmp/<host>-<pid>/ each runner's scratch
#pragma once

#include "orchestration/csv.h"
#include "orchestration/expand.h"

#include <cstdint>
#include <string>
#include <vector>

namespace arcs {

// Which part of an experiment's cases a run does: shard `index` of `count`.
struct Shard {
  int index = 0;
  int count = 1;           // 1 = all cases (results.csv)
  std::string source;      // "--shard", "SLURM_ARRAY_TASK_ID" or "" (not sharded)
  bool sharded() const { return count > 1; }
  std::string Text() const { return std::to_string(index) + "/" + std::to_string(count); }
};

// Parses "I/N" (0 <= I < N). Throws Error naming `what` on anything else.
Shard ParseShard(const std::string& text, const std::string& what = "--shard");

// The shard of a Slurm array task: SLURM_ARRAY_TASK_ID (minus
// SLURM_ARRAY_TASK_MIN, divided by SLURM_ARRAY_TASK_STEP) of
// SLURM_ARRAY_TASK_COUNT; {0, 1} outside an array job.
Shard ShardFromEnvironment();

// The cases of `shard`, in expansion order. The partition is stable: it
// depends only on the experiment's cases (their ids and swept values) and N,
// not on the order of files or on other shards. It is cost-aware: cases are
// ranked by the product of their numeric swept values (the expensive n's
// first; ties by case id) and dealt round-robin, so each shard gets its share
// of the expensive ones.
std::vector<const Case*> ShardCases(const std::vector<Case>& cases, const Shard& shard);

// "results.csv" unsharded, else "results.<I>-of-<N>.csv".
std::string ResultsFileName(const Shard& shard);

// Every results file of DIR (results.csv first, then the shard files by name).
std::vector<std::string> ResultsFiles(const std::string& dir);

// Length of the longest prefix of the CSV text that ends with a complete row
// (a newline outside quotes whose row has as many fields as the header).
size_t CompleteCsvPrefix(const std::string& text);

// Truncates a CSV file's torn tail (a last row cut by a full disk, a crash or
// power loss) to the last complete row. Returns the number of bytes dropped
// (0 when the file is whole or absent).
std::uintmax_t RepairTornTail(const std::string& path);

// The union of DIR's results files: the header is the union of theirs (in
// order of first appearance), rows are deduplicated by case_id (the last `ok`
// row wins, else the last row). A torn tail in a file being written is left
// out (the file itself is not changed). Throws Error when there is no
// results file. Warnings: cases the experiment has that no file has yet.
CsvTable ReadResultsDir(const std::string& dir, std::vector<std::string>* warnings = nullptr);

// The union of several runs' results, merged as ReadResultsDir merges one
// directory's files: each source a results directory (all its files) or one
// results .csv file (e.g. a part of a long table kept in the repository,
// docs/runs/). A run made in parts (other grids, meshes or methods, other
// sessions) gives one table. Throws Error naming a source that is neither.
CsvTable ReadResults(const std::vector<std::string>& sources, std::vector<std::string>* warnings = nullptr);

// An exclusive advisory lock (flock) on a file, released when the object
// dies or the process does (kill -9 included).
class FileLock {
 public:
  FileLock() = default;
  ~FileLock();
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;
  // Non-blocking: false when another process holds it; `holder` then gets
  // what that process wrote into the lock file ("pid 123 on host h since T: what").
  bool TryLock(const std::string& path, const std::string& what, std::string* holder);
  // Blocks until the lock is ours.
  void Lock(const std::string& path);
  void Unlock();

 private:
  int fd_ = -1;
};

// The experiment's identity: a hash of its sorted case ids (so of every
// resolved setting that reaches a result: items, normalisation, pipelines and
// their parameters, metrics, seed), 16 hex digits.
std::string ExperimentIdentity(const std::vector<Case>& cases);

// Throws Error when DIR holds another experiment's results (see
// ClaimResultsDir); reads only, takes no lock.
void CheckResultsDir(const std::string& dir, const Experiment& exp, const std::vector<Case>& cases);

// Claims DIR for the experiment, under DIR's setup lock: writes
// experiment.id when absent, and refuses (Error) when DIR holds another
// experiment's results — a different experiment.id, or, in a directory from
// before experiment.id existed, rows whose case ids the experiment does not
// have. Writes config.resolved.yaml (atomically) and appends `provenance`
// (one YAML document) to provenance.yaml.
void ClaimResultsDir(const std::string& dir, const Experiment& exp, const std::vector<Case>& cases,
                     const std::string& resolved_config, const std::string& provenance);

}  // namespace arcs
