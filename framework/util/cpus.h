// How many CPUs this process may use: its CPU allocation, not the machine's
// core count. A Slurm task with --cpus-per-task=C gets C; `taskset -c 0` gets 1.
#pragma once

#include <string>

namespace arcs {

struct CpuAllocation {
  int cpus = 1;            // at least 1
  std::string source;      // "SLURM_CPUS_PER_TASK", "sched_getaffinity" or "hardware_concurrency"
  int affinity_cpus = 0;   // CPUs in this process's affinity mask (0 = unknown)
  int slurm_cpus = 0;      // $SLURM_CPUS_PER_TASK (0 = unset or not a positive integer)
};

// SLURM_CPUS_PER_TASK when set (capped by the affinity mask when that is
// smaller), else the affinity mask's CPU count, else hardware_concurrency().
CpuAllocation AvailableCpus();

}  // namespace arcs
