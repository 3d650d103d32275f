// dual_contouring: classic dual contouring (Ju et al. 2002) of grid SDF
// samples; optionally manifold (one vertex per marching-cubes sheet).
#include "framework/sdfmesh/dual_contouring.h"
#include "framework/sdfmesh/sdf_input.h"
#include "registry/bind.h"
#include "stages/builtin.h"

namespace arcs {

namespace {

Binder<DualContouringOptions> DualContouringParams() {
  using O = DualContouringOptions;
  return Binder<O>()
      .Double("level", &O::isovalue, "iso-value extracted (a node is inside iff its value < level)")
      .Double("svd_threshold", &O::svd_threshold,
              "QEF: singular values below this fraction of the largest are dropped (Ju et al.: 0.1)",
              HalfOpen(0.0, 1.0))
      .Enum("normals", &O::normals, kDcNormalsNames,
            "Hermite normals: one per edge, the gradient of the trilinear interpolants averaged over the edge's "
            "cells (central differences across the edge), or each cell's own trilinear gradient at the point "
            "(mean Hausdorff on 4 CAD bench meshes at n=20/40: edge 0.114/0.038, trilinear 0.130/0.050, MC "
            "0.127/0.055)")
      .Bool("clamp_to_cell", &O::clamp_to_cell, "move a vertex the QEF puts outside its cell onto the cell's box")
      .Bool("manifold", &O::manifold,
            "one vertex per marching-cubes sheet of a cell (manifold output, MC's topology) instead of one per cell");
}

void RunDualContouring(Context&, CaseData& d, const DualContouringOptions& o, const ParamMap&) {
  const SdfSamples& sm = *d.samples;
  CheckSdfToMeshInput(sm, "dual_contouring", /*need_grid=*/true, o.isovalue);
  DualContouringStats st;
  Mesh m = DualContouring(sm.values, *sm.grid, o, &st);
  if (m.Empty()) throw Error("the level set crosses no interior grid edge: empty mesh");
  d.SetMetric("dc_clamped", st.clamped);
  d.SetMetric("dc_multi_sheet_cells", st.multi_sheet_cells);
  d.output = std::move(m);
}

}  // namespace

void RegisterDualContouring(Registry& r) {
  StageInfo s = DeclareStage(
      "dual_contouring", Role::kSdfToMesh,
      "dual contouring (Ju et al. 2002) on grid SDF samples: Hermite points on crossed edges, QEF vertex per "
      "cell by truncated SVD about the mass point, one quad per crossed edge split in two triangles",
      {Slot::kSamples}, {Slot::kOutput}, k3D);
  BindStage<DualContouringOptions>(s, DualContouringParams(), RunDualContouring);
  s.outputs = {"dc_clamped", "dc_multi_sheet_cells"};
  r.Register(std::move(s));
}

}  // namespace arcs
