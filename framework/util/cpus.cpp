#include "framework/util/cpus.h"

#include <sched.h>

#include <algorithm>
#include <cstdlib>
#include <string>
#include <thread>

namespace arcs {

CpuAllocation AvailableCpus() {
  CpuAllocation a;
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) == 0) a.affinity_cpus = CPU_COUNT(&set);
  if (const char* s = std::getenv("SLURM_CPUS_PER_TASK")) {
    char* end = nullptr;
    const long v = std::strtol(s, &end, 10);
    if (*s && !*end && v > 0 && v < 1 << 20) a.slurm_cpus = static_cast<int>(v);
  }
  if (a.slurm_cpus > 0) {
    a.cpus = a.affinity_cpus > 0 ? std::min(a.slurm_cpus, a.affinity_cpus) : a.slurm_cpus;
    a.source = "SLURM_CPUS_PER_TASK";
  } else if (a.affinity_cpus > 0) {
    a.cpus = a.affinity_cpus;
    a.source = "sched_getaffinity";
  } else {
    a.cpus = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    a.source = "hardware_concurrency";
  }
  a.cpus = std::max(1, a.cpus);
  return a;
}

}  // namespace arcs
