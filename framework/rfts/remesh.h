// Local isotropic remeshing (Botsch & Kobbelt 2004) of a closed manifold
// triangle mesh, restricted to a patch of "active" faces: the remeshing step
// of Reach for the Spheres (Sellán et al. 2023; ../shared/notes/baselines.md).
//
// One iteration = (1) split every edge longer than split_ratio·h, (2) collapse
// every edge shorter than collapse_ratio·h into its midpoint unless that makes
// an edge longer than split_ratio·h, flips a face normal or breaks the link
// condition, (3) flip edges that bring the valences of their four vertices
// closer to 6, (4) tangential relaxation of every free vertex toward the
// uniform average of its neighbours, (5) projection of the free vertices onto
// the mesh as it was before the call.
//
// The patch: only edges whose two faces are active are split or flipped
// (faces made from an active face are active); only edges whose two vertices
// are free (every incident face active) are collapsed; only free vertices
// move. So the patch boundary and everything outside stay exactly as they
// were. Serial and deterministic (edges are visited in index order).
//
// Ours, not CGAL's isotropic_remeshing: the RFTS flow remeshes a small patch
// at every one of up to 20 000 iterations, so the per-call overhead (CGAL's
// Surface_mesh / property maps / AABB tree construction per call) would
// dominate; the operations are the textbook ones (docs/rfts.md).
#pragma once

#include "framework/types.h"

#include <vector>

namespace arcs {

struct RemeshOptions {
  double target_edge_length = 0.1;  // h (same units as the mesh)
  double split_ratio = 1.4;         // split edges longer than ratio·h (RFTS notes: 1.4)
  double collapse_ratio = 0.7;      // collapse edges shorter than ratio·h (RFTS notes: 0.7)
  int iterations = 1;               // rounds of split/collapse/flip/relax/project (RFTS: 1 per flow step)
  bool project = true;              // project moved vertices onto the input mesh
  void Check() const;
};

struct RemeshStats {
  int splits = 0, collapses = 0, flips = 0, relaxed = 0;
};

// Remeshes `mesh` in place. `active_faces` (one flag per face, or empty =
// every face active) marks the patch. Throws InputError unless the mesh is a
// closed, edge-manifold, consistently oriented triangle mesh with valid
// indices. The output has no unreferenced vertices; faces and vertices are
// renumbered (kept in their relative order, new ones appended).
RemeshStats RemeshPatch(Mesh* mesh, const std::vector<char>& active_faces, const RemeshOptions& options);

}  // namespace arcs
