// The list of built-in stages: one place anyone can grep.
#pragma once

#include "registry/registry.h"

namespace arcs {

// Registers every built-in stage into `registry` (explicitly; no static
// self-registration, which static linking can silently drop).
void RegisterBuiltinStages(Registry& registry);

// Per-family registration functions (each in its own translation unit).
void RegisterSdfGrid(Registry& r);
void RegisterSdfRandom(Registry& r);
void RegisterSdfFile(Registry& r);
void RegisterSdfNoise(Registry& r);
void RegisterSdfClamp(Registry& r);
void RegisterSdfSweep(Registry& r);
void RegisterMarchingCubes(Registry& r);
void RegisterRfts(Registry& r);  // Reach for the Spheres (stages/baseline/rfts.cpp)
// SDF -> mesh baselines beside MC (stages/baseline/; framework/sdfmesh/).
void RegisterDualContouring(Registry& r);
void RegisterDcsdd(Registry& r);
void RegisterVdbMesher(Registry& r);
void RegisterPowerDiagram(Registry& r);
void RegisterEvalStages(Registry& r);
// Surface reconstructors (oriented points -> mesh; stages/reconstruct/).
void RegisterScreenedPoisson(Registry& r);
// RFTA: empty-space samplers and the arc projector (stages/rfta/).
void RegisterRasterize(Registry& r);
void RegisterRejection(Registry& r);
void RegisterMetropolisHastings(Registry& r);
void RegisterArcProjector(Registry& r);
// RFTA: fine-tuning and the whole method as one stage (stages/rfta/).
void RegisterFineTune(Registry& r);
void RegisterRfta(Registry& r);
// Winding-number voxelization and mesh morphing (stages/voxel/).
void RegisterVoxelStages(Registry& r);
void RegisterMorphStages(Registry& r);
// Point clouds: inputs (sampling, noise, normal estimation) and the
// point-cloud reconstructors (stages/points/).
void RegisterPointInputStages(Registry& r);
void RegisterGraphVoronoi(Registry& r);
void RegisterPointReconstructors(Registry& r);
// 2D twins, each beside its 3D sibling (the 2D path of Reach for the Arcs;
// 2D RFTA is the `rfta` stage on dim-2 samples).
void RegisterSdfGrid2D(Registry& r);            // stages/sdf/sdf_grid_2d.cpp
void RegisterSdfRandom2D(Registry& r);          // stages/sdf/sdf_random_2d.cpp
void RegisterMarchingSquares(Registry& r);      // stages/baseline/marching_squares.cpp
void RegisterScreenedPoisson2D(Registry& r);    // stages/reconstruct/screened_poisson_2d.cpp
void RegisterEvalStages2D(Registry& r);         // stages/eval/eval_stages_2d.cpp

}  // namespace arcs
