// The built-in stages: one line per registration function, in the order
// they register. Adding a stage is one file (stages/<family>/<name>.cpp,
// defining `void RegisterX(Registry& r)`) plus one line here; the glob in
// stages/CMakeLists.txt builds the file. Included twice by stages/builtin.*:
// once to declare the functions, once to call them.
// No include guard: it is meant to be included more than once.

// SDF samplers and modifiers (mesh -> SDF samples; stages/sdf/).
ARCS_BUILTIN_STAGE(RegisterSdfGrid)
ARCS_BUILTIN_STAGE(RegisterSdfRandom)
ARCS_BUILTIN_STAGE(RegisterSdfFile)
ARCS_BUILTIN_STAGE(RegisterSdfNoise)
ARCS_BUILTIN_STAGE(RegisterSdfClamp)
ARCS_BUILTIN_STAGE(RegisterSdfSweep)
// SDF -> mesh baselines (stages/baseline/; framework/sdfmesh/, framework/rfts/).
ARCS_BUILTIN_STAGE(RegisterMarchingCubes)
ARCS_BUILTIN_STAGE(RegisterRfts)
ARCS_BUILTIN_STAGE(RegisterDualContouring)
ARCS_BUILTIN_STAGE(RegisterDcsdd)
ARCS_BUILTIN_STAGE(RegisterVdbMesher)
ARCS_BUILTIN_STAGE(RegisterPowerDiagram)
// RFTA: empty-space samplers, arc projector, fine-tuning, the whole method (stages/rfta/).
ARCS_BUILTIN_STAGE(RegisterRasterize)
ARCS_BUILTIN_STAGE(RegisterRejection)
ARCS_BUILTIN_STAGE(RegisterMetropolisHastings)
ARCS_BUILTIN_STAGE(RegisterArcProjector)
ARCS_BUILTIN_STAGE(RegisterFineTune)
ARCS_BUILTIN_STAGE(RegisterRfta)
// Surface reconstructors (oriented points -> mesh; stages/reconstruct/, stages/points/).
ARCS_BUILTIN_STAGE(RegisterScreenedPoisson)
ARCS_BUILTIN_STAGE(RegisterGraphVoronoi)
ARCS_BUILTIN_STAGE(RegisterPointReconstructors)
// Point-cloud inputs: sampling, noise, normal estimation (stages/points/).
ARCS_BUILTIN_STAGE(RegisterPointInputStages)
// Winding-number voxelization and mesh morphing (stages/voxel/).
ARCS_BUILTIN_STAGE(RegisterVoxelStages)
ARCS_BUILTIN_STAGE(RegisterMorphStages)
// 2D twins, each beside its 3D stage (stages/sdf/, baseline/, reconstruct/, eval/).
ARCS_BUILTIN_STAGE(RegisterSdfGrid2D)
ARCS_BUILTIN_STAGE(RegisterSdfRandom2D)
ARCS_BUILTIN_STAGE(RegisterMarchingSquares)
ARCS_BUILTIN_STAGE(RegisterScreenedPoisson2D)
ARCS_BUILTIN_STAGE(RegisterEvalStages2D)
// Evaluators (stages/eval/).
ARCS_BUILTIN_STAGE(RegisterEvalStages)
