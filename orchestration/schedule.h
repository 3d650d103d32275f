// Scheduling an experiment's cases: each in a forked worker process (at
// most `jobs` at a time, killed after case_timeout_s; a crash or a kill is a
// failed row, the run goes on), or one after another in this process. Rows
// come back through ScheduleHooks::finished as each case ends, in the
// runner's process. SIGINT/SIGTERM stop the schedule: no new case starts,
// running workers are ended, and RunSchedule returns true.
#pragma once

#include "orchestration/case_exec.h"
#include "orchestration/expand.h"

#include <functional>
#include <string>
#include <vector>

namespace arcs {

struct ScheduleOptions {
  int jobs = 1;               // workers at once (at least 1)
  bool isolate = true;        // each case in a forked worker process (else in this process)
  double case_timeout_s = 0;  // a worker running longer is killed (0 = never)
  std::string tmp_dir;        // where workers leave their rows (must exist)
};

struct ScheduleHooks {
  std::function<Row(const Case&)> execute;             // runs one case (in the worker)
  std::function<void(const Case&)> started;            // a case began
  std::function<void(const Case&, Row)> finished;      // its row (ok, failed, crashed, timed out)
};

// Runs `todo` in order; returns whether it was interrupted.
bool RunSchedule(const std::vector<const Case*>& todo, const ScheduleOptions& o, const ScheduleHooks& hooks);

}  // namespace arcs
