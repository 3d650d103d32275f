// Input checks shared by the SDF -> mesh baselines (dual contouring, DCSDD,
// OpenVDB, power diagram): every one of them refuses unusable samples with an
// error that names the stage and what is wrong, before any work.
#pragma once

#include "framework/types.h"

#include <string>

namespace arcs {

// Throws arcs::Error("<who>: ...") unless `samples` are 3D, have as many
// points as values (and, when a grid is set, as many values as grid nodes),
// at least 2 samples, finite coordinates and values, and values on both sides
// of `isovalue` (all-positive or all-negative samples hold no surface).
// With `need_grid`, the samples must be the nodes of a regular 3D grid with
// at least 2 nodes and a positive spacing on every axis.
void CheckSdfToMeshInput(const SdfSamples& samples, const std::string& who, bool need_grid,
                         double isovalue = 0.0);

}  // namespace arcs
