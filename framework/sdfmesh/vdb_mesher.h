// OpenVDB's mesher (tools::volumeToMesh, OpenVDB 10, Debian libopenvdb-dev)
// on SDF values on a regular grid: the industry's SDF mesher, a dual
// (surface-nets-like) scheme with one vertex per cell at the mean of the
// cell's edge crossings (no QEF), quads, and an adaptivity parameter that
// merges flat regions into larger polygons.
//
// The grid's nodes become the voxels of an openvdb::FloatGrid (every node an
// active voxel, index (i, j, k) -> the node's position through a scale and
// translation), the background (outside the grid) is positive; quads are
// split along the shorter diagonal; OpenVDB already winds faces outward
// (towards values above the isovalue).
#pragma once

#include "framework/types.h"

namespace arcs {

struct VdbMesherOptions {
  double isovalue = 0.0;                    // level extracted (OpenVDB's default 0)
  double adaptivity = 0.0;                  // 0 = uniform mesh, 1 = maximal merging of flat regions (OpenVDB's default 0)
  bool relax_disoriented_triangles = true;  // OpenVDB's option of that name (its default true)
  void Check() const;
};

// Whether arcs was built with OpenVDB (ARCS_WITH_OPENVDB); without it
// VdbVolumeToMesh throws.
bool VdbMesherAvailable();

// `values` in GridInfo order, grid.dim == 3, dims >= 2, finite.
Mesh VdbVolumeToMesh(const VectorXd& values, const GridInfo& grid, const VdbMesherOptions& options = {});

}  // namespace arcs
