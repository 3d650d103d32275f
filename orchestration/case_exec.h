// Executing one case in this process: load and normalise its dataset item,
// run the input pipeline, the method (timed, with its peak memory), then the
// metrics; the results row. The runner (runner.h) calls it in a worker.
#pragma once

#include "framework/context.h"
#include "orchestration/expand.h"
#include "registry/registry.h"

#include <string>
#include <utility>
#include <vector>

namespace arcs {

using Row = std::vector<std::pair<std::string, std::string>>;

// Runs one case in this process and returns its results row (status "ok" or
// "failed" with the error message; never throws for a case's own failure).
// `threads` limits the case's parallelism (0 = all cores). With
// `outputs_dir`, the method's output is written there (see OutputStem): the
// mesh as <stem>.ply, a 2D curve as <stem>.obj, and, for datasets that are not
// point clouds, the method's oriented points (RFTA's tangency points) as
// <stem>_points.ply; all in the case's normalised frame, the reference's.
Row ExecuteCase(const Case& c, const Registry& registry, int threads, const Context::LogFn& log,
                const std::string& outputs_dir = {});

// File stem of a case's saved output: item, the varying parameters, input
// and method, then the case id (unique), e.g. "bunny_n=20__grid__RFTA__1a2b...".
std::string OutputStem(const Case& c);

}  // namespace arcs
