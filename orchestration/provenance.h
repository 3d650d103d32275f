// Provenance of a run: the resolved configuration it saves
// (config.resolved.yaml, re-runnable as an experiment file), the record of
// where and how it ran (provenance.yaml), and the facts both draw on (build
// revision: version.h; process memory: memory.h).
#pragma once

#include "framework/util/cpus.h"
#include "orchestration/runner.h"

#include <yaml-cpp/yaml.h>

#include <string>

namespace arcs {

// The document after overrides, with every pipeline stage's parameters
// completed from the schema (swept ones keep their lists), the seed written
// out, dataset files and reference CSVs made absolute: an experiment file
// that gives the same cases from anywhere.
YAML::Node ResolvedConfig(const Experiment& exp, const Registry& registry);

// One provenance.yaml document (YAML text): versions, git state, host, CPUs
// (and Slurm's variables), the experiment, seed, jobs, threads, shard,
// command line, the plugins loaded.
std::string ProvenanceText(const Experiment& exp, const RunOptions& o, int threads, const CpuAllocation& cpu,
                           const std::string& experiment_id);

// Local time, ISO 8601 with offset ("2026-12-02T01:02:03+0000").
std::string LocalTimeNow();
// This machine's host name.
std::string Hostname();

}  // namespace arcs
