// The 2D screened Poisson stage (stages/reconstruct/screened_poisson_2d.cpp)
// as the reconstructor of the RFTA stages (rfta, fine_tune) on 2D samples.
#pragma once

#include "registry/registry.h"

namespace arcs {

// The reconstructor RFTA uses on 2D samples for the configured `spec`: the
// 3D default `screened_poisson` becomes `screened_poisson_2d` with its
// defaults, except that a negative depth_offset d (RFTA's coarse tuning
// reconstructor: -3) becomes resolution_shift -ceil(-d/3) (-1: half the
// cells per side); its other parameters are dropped. Any other stage is kept
// (it must write CaseData::output_curve). Throws Error if `registry` is null.
StageSpec PlanarReconstructorFor(const StageSpec& spec, const Registry* registry);

}  // namespace arcs
