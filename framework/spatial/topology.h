// Combinatorial topology of a triangle mesh.
#pragma once

#include "framework/types.h"

namespace arcs {

struct Topology {
  int vertices = 0;               // #V (all rows of V)
  int referenced_vertices = 0;    // vertices used by at least one face
  int faces = 0;
  int edges = 0;                  // undirected edges
  int components = 0;             // connected components of faces (via shared vertices)
  int boundary_edges = 0;         // edges with one incident face
  int nonmanifold_edges = 0;      // edges with more than two incident faces
  int nonmanifold_vertices = 0;   // vertices whose incident faces form more than one fan
  int degenerate_faces = 0;       // faces with a repeated index or zero area
  bool closed = false;            // no boundary edges (and at least one face)
  bool edge_manifold = false;     // every edge has 1 or 2 faces
  bool manifold = false;          // edge- and vertex-manifold
  bool oriented = false;          // every interior edge used once in each direction
  int euler = 0;                  // V_referenced - E + F
  // Total genus sum_c (2 - chi_c) / 2 over components; -1 when not a closed
  // oriented manifold (genus undefined).
  int genus = -1;
  double area = 0.0;
  double volume = 0.0;            // signed (divergence theorem); > 0 for outward closed meshes
};

// Throws InputError on a face index outside [0, #V). Conventions: an edge is
// an unordered vertex pair used by at least one face (collapsed edges of faces
// with a repeated index are skipped); a face is degenerate when it repeats an
// index or |cross| <= 1e-12 * (longest edge)^2; `oriented` fails when a
// directed edge occurs twice.
Topology ComputeTopology(const Mesh& mesh);

// The connected component of every face (faces sharing a vertex are one
// component, as in ComputeTopology), numbered 0, 1, ... in the order of each
// component's first face. `count` (optional) receives the number of
// components. Face indices must be valid (CheckMeshIndices).
std::vector<int> FaceComponents(const Mesh& mesh, int* count = nullptr);

// Throws InputError("<who>: face f has vertex index i, the mesh has n
// vertices") unless every face index is in [0, #V) and, with `finite`, every
// vertex used by a face has finite coordinates.
void CheckMeshIndices(const Mesh& mesh, const char* who, bool finite = false);

}  // namespace arcs
