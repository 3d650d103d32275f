// The voxelize and morph stages' parameters, declared once (registry/bind.h)
// and shared by the stages and the `arcs voxelize` / `arcs morph` commands,
// whose flags, help lines, defaults and decoding come from these binders.
#pragma once

#include "framework/error.h"
#include "framework/voxel/doph_protocol.h"
#include "framework/voxel/morph.h"
#include "framework/voxel/voxelize.h"
#include "registry/bind.h"

#include <cmath>

namespace arcs {

// The voxelize stage's settings: the grid (stage-level) and the algorithm's options.
struct VoxelizeStageOptions {
  int resolution = 128;  // grid nodes per axis
  VoxelizeOptions voxelize;
  double lo = -1.0, hi = 1.0;  // the grid's box [lo, hi]^3
  void Check() const {
    ARCS_CHECK_OPTION(resolution >= 2 && resolution <= 2048, "resolution", resolution, "an integer in [2, 2048]");
    voxelize.Check();
    if (!(std::isfinite(lo) && std::isfinite(hi) && lo < hi))
      throw OptionError("lo = " + std::to_string(lo) + ", hi = " + std::to_string(hi) + ": must be finite with lo < hi");
  }
};

inline Binder<VoxelizeOptions> VoxelizeOptionParams() {
  using O = VoxelizeOptions;
  return Binder<O>()
      .Choice("method", &O::method, {"fast", "exact", "naive", "ray_parity"},
              "fast: exact sign by flood fill (closed) or hierarchy + exact band (open); exact: O(#F) sum per node; "
              "naive: eq. 4; ray_parity: Embree parity")
      .Choice("output", &O::output, {"occupancy", "winding"}, "volume values: 0/1 occupancy or the winding number")
      .Choice("open_mesh", &O::open_mesh, {"auto", "none", "flip_dup"},
              "auto: threshold + thin shell on sheet faces; none: threshold; flip_dup: the paper's Alg. 2")
      .Choice("orientation", &O::orientation, {"abs", "as_is"}, "abs: |w| > 1/2 (inward meshes work); as_is: w > 1/2")
      .Double("epsilon", &O::epsilon, "Alg. 2 offset (paper 0.01); auto: minimum shell thickness", Closed(0.0, 1e9))
      .Double("beta", &O::beta, "hierarchy far-field acceptance ratio (open meshes)", Closed(1.0, 1e9))
      .Double("exact_band", &O::exact_band, "hierarchy: exact sum where ||w| - 1/2| < band", Closed(0.0, 0.5));
}

inline Binder<VoxelizeStageOptions> VoxelizeParams() {
  using S = VoxelizeStageOptions;
  return Binder<S>()
      .Int("resolution", &S::resolution, "grid nodes per axis (paper: 32, 64, 128, 256)", Closed(2, 2048))
      .Group(&S::voxelize, VoxelizeOptionParams())
      .Double("lo", &S::lo, "grid lower bound on every axis (paper: meshes normalised to [-1, 1])")
      .Double("hi", &S::hi, "grid upper bound on every axis");
}

// The morph stage's settings: the target grid and source sphere (stage-level) and the algorithm's options.
struct MorphStageOptions {
  int res = 64;           // grid nodes per axis when the reference is voxelized by the stage
  int subdivisions = 3;   // icosphere subdivisions of the source
  MorphOptions morph;
  void Check() const {
    ARCS_CHECK_OPTION(res >= 4 && res <= 512, "res", res, "an integer in [4, 512]");
    ARCS_CHECK_OPTION(subdivisions >= 0 && subdivisions <= 7, "subdivisions", subdivisions, "an integer in [0, 7]");
    morph.Check();
  }
};

inline Binder<SoftOccupancyOptions> SoftOccupancyParams() {
  using O = SoftOccupancyOptions;
  return Binder<O>()
      .Enum("form", &O::form, kWindingFormNames,
            "winding number of the loss: eq. 4 naive (paper's morphing) or Alg. 1 solid angle")
      .Enum("occupancy", &O::map, kOccupancyMapNames, "occupancy from w (paper: identity)")
      .Double("sharpness", &O::sharpness, "sigmoid sharpness (occupancy: sigmoid)", LeftOpen(0.0, 1e6));
}

inline Binder<OccupancyLossOptions> OccupancyLossParams() {
  using O = OccupancyLossOptions;
  return Binder<O>()
      .Group(&O::occupancy, SoftOccupancyParams())
      .Enum("loss", &O::loss, kOccupancyLossNames, "per-node loss");
}

inline Binder<MorphOptions> MorphOptionParams() {
  using O = MorphOptions;
  return Binder<O>()
      .Int("iterations", &O::iterations, "Adam steps", Closed(0, 100000))
      .Double("lr", &O::lr, "Adam learning rate (units of the grid's frame)", LeftOpen(0.0, 1.0))
      .Double("smooth", &O::smooth, "uniform-Laplacian energy weight", Closed(0.0, 1e9))
      .Int("batch", &O::batch, "grid nodes per step (0 = whole active set)", Closed(0, 100000000))
      .Double("random_fraction", &O::random_fraction, "share of the batch drawn uniformly from the grid",
              Closed(0.0, 1.0))
      .Int("band", &O::band, "active band half-width around both surfaces, voxels", Closed(1, 64))
      .Int("refresh_every", &O::refresh_every, "steps between active-set refreshes and IoU logs", Closed(1, 100000))
      .Double("softening", &O::softening_voxels, "softening of the eq. 4 kernel, voxels (0 = eq. 4 as printed)",
              Closed(0.0, 100.0))
      .Group(&O::loss, OccupancyLossParams())
      .Enum("residual", &O::residual, kMorphResidualNames,
            "soft: gradient of the loss; exact: hard-occupancy residual through the form's gradient");
}

inline Binder<MorphStageOptions> MorphParams() {
  using S = MorphStageOptions;
  return Binder<S>()
      .Int("res", &S::res, "grid nodes per axis when the reference is voxelized here (ignored with a volume)",
           Closed(4, 512))
      .Int("subdivisions", &S::subdivisions, "icosphere subdivisions of the source (20*4^s faces)", Closed(0, 7))
      .Group(&S::morph, MorphOptionParams());
}

}  // namespace arcs
