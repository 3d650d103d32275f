// Inside or outside of a closed triangle mesh from a query's closest point
// (Bærentzen & Aanæs 2005): q is outside iff (q - p) · n > 0, where p is the
// closest point on the surface and n the pseudonormal of the feature p lies
// on — the face normal inside a face, the sum of the two face normals on an
// edge, the angle-weighted sum of the incident face normals at a vertex. For
// a closed, manifold, consistently oriented mesh this is exact for every q
// off the surface, and it costs nothing beyond the closest-point query that
// a caller often makes anyway (RFTA's fine-tuning asks both of every sphere
// centre). The fast winding number (winding_number.h) needs no closed mesh
// but is approximate in its far field, largest at centres of curvature.
#pragma once

#include "framework/types.h"

#include <vector>

namespace arcs {

class PseudonormalSign {
 public:
  // Face normals and the edge adjacency (parallel, deterministic); the edge
  // and vertex pseudonormals are formed when a query lands on that feature
  // (RFTA asks one query per sphere centre of a surface with several times
  // as many vertices, and most closest points lie inside a face). Throws
  // InputError on a face index outside [0, #V).
  explicit PseudonormalSign(const Mesh& mesh);
  // Every edge has exactly two faces that traverse it in opposite
  // directions: the condition for Side to be exact. Side answers 0 otherwise.
  bool closed() const { return closed_; }
  // +1 outside, -1 inside; 0 undecided: the mesh is not closed, q is on the
  // surface (or within rounding of its tangent plane), or the feature's
  // pseudonormal vanishes (degenerate faces). `p` is q's closest point on
  // the mesh and `face` a face it lies on (TriangleBvh::Hit).
  int Side(const Vec3& q, const Vec3& p, int face) const;

 private:
  // The angle-weighted pseudonormal of vertex v; zero where v's faces do
  // not form one fan (two fans meeting at v have none).
  Vec3 VertexNormal(int v) const;

  const Mesh* mesh_;
  bool closed_ = false;
  std::vector<Vec3> face_n_;   // unit face normals (zero if degenerate)
  // Outgoing half-edges per vertex (CSR): half-edge 3f + k goes from corner
  // k to corner k + 1 of face f. Each face meets a vertex in exactly one
  // outgoing half-edge, so a vertex's list is also its faces.
  std::vector<int> start_, out_;
  std::vector<int> twin_of_;   // per half-edge, its twin (closed meshes only)
};

}  // namespace arcs
