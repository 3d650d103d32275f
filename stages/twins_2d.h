// The 2D twin of each 3D stage that has one: the one place that says which
// stage does a 3D stage's job on dim-2 cases (curves, paper Fig. 5). RFTA's
// parts (rasterize, rejection, metropolis_hastings, arc_projector, fine_tune)
// and `rfta` itself have no twin: one stage serves both dimensions, the
// library dispatching on samples.dim (framework/rfta/reach_for_the_arcs.h).
// The rfta and fine_tune stages run a configured 3D reconstructor's twin on
// 2D samples (PlanarReconstructorFor, stages/reconstruct/screened_poisson_2d.h).
// Still apart: each twin keeps its own name, parameters and metric columns
// (chamfer vs chamfer_2d), since CaseData has separate 3D and 2D slots.
#pragma once

#include <string>

namespace arcs {

struct StageTwin {
  const char* stage_3d;
  const char* stage_2d;
};

inline constexpr StageTwin kStageTwins2D[] = {
    {"sdf_grid", "sdf_grid_2d"},       {"sdf_random", "sdf_random_2d"}, {"marching_cubes", "marching_squares"},
    {"screened_poisson", "screened_poisson_2d"}, {"chamfer", "chamfer_2d"}, {"hausdorff", "hausdorff_2d"},
    {"e_sdf", "e_sdf_2d"},             {"topology", "topology_2d"},
};

// The 2D twin of the 3D stage `stage`, or "" if it has none.
inline std::string TwinIn2D(const std::string& stage) {
  for (const StageTwin& t : kStageTwins2D)
    if (stage == t.stage_3d) return t.stage_2d;
  return "";
}

}  // namespace arcs
