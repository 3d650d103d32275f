#include "framework/rfta/component_filter.h"

#include "framework/rfta/sphere_set.h"
#include "framework/rfta/sphere_tree.h"
#include "framework/spatial/topology.h"
#include "framework/spatial/triangle_bvh.h"
#include "framework/util/parallel.h"

#include <algorithm>
#include <vector>

namespace arcs {

ComponentFilterStats DropInfeasibleComponents(Mesh* mesh, const SdfSamples& samples, double tol,
                                              double max_inside_fraction) {
  ComponentFilterStats st;
  const int nv = mesh->NumVertices(), nf = mesh->NumFaces();
  if (nf == 0 || samples.Size() == 0) return st;
  // Vertex -> component (through its faces); -1 for unreferenced vertices.
  int nc = 0;
  const std::vector<int> face_comp = FaceComponents(*mesh, &nc);
  std::vector<int> comp(nv, -1);
  for (int f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) comp[mesh->F(f, k)] = face_comp[f];
  st.components = nc;
  if (nc <= 1) return st;
  MatrixX3d centers(samples.Size(), 3);
  VectorXd radii(samples.Size());
  std::vector<int> ids(samples.Size());
  for (Eigen::Index i = 0; i < samples.Size(); ++i) {
    centers.row(i) = SamplePoint(samples, i).transpose();
    radii[i] = std::abs(samples.values[i]);
    ids[i] = static_cast<int>(i);
  }
  std::vector<int> nverts(nc, 0), ninside(nc, 0), nfaces(nc, 0);
  for (int f = 0; f < nf; ++f) ++nfaces[face_comp[f]];
  const int largest = static_cast<int>(std::max_element(nfaces.begin(), nfaces.end()) - nfaces.begin());
  // The largest component is never a candidate, so its vertices (most of
  // the mesh) need no containment test.
  const SphereTree tree(centers, radii, ids);
  std::vector<char> inside(nv, 0);
  ParallelFor(nv, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t v = b; v < e; ++v)
      if (comp[v] >= 0 && comp[v] != largest) inside[v] = tree.AnyContains(mesh->V.row(v).transpose(), -tol, -1);
  });
  for (int v = 0; v < nv; ++v) {
    if (comp[v] < 0) continue;
    ++nverts[comp[v]];
    ninside[comp[v]] += inside[v];
  }
  std::vector<int> candidates;
  for (int c = 0; c < nc; ++c)
    if (c != largest && ninside[c] > max_inside_fraction * nverts[c]) candidates.push_back(c);
  if (candidates.empty()) return st;
  // The samples' verdict on each candidate: its removal must not worsen the
  // fit of the samples, sum_i (|s_i| - dist(p_i, surface))^2 (the paper's
  // E_SDF terms). Only samples whose closest face is in the candidate change
  // distance. A surface part slightly fatter than the samples allow (a thin
  // feature at a coarse grid) has most vertices inside spheres yet is the
  // only surface near its samples: removing it would leave them far from
  // any surface, so it stays; a bubble inside the free space fits no sample
  // better than the surface beyond it, so it goes.
  VectorXd sq;
  Eigen::VectorXi closest_face;
  const TriangleBvh whole(*mesh, /*oriented_boxes=*/false);
  whole.ClosestPoints(centers, &sq, nullptr, &closest_face);
  std::vector<char> drop(nc, 0);
  for (int c : candidates) {
    std::vector<int> near;
    for (Eigen::Index i = 0; i < centers.rows(); ++i)
      if (closest_face[i] >= 0 && face_comp[closest_face[i]] == c) near.push_back(static_cast<int>(i));
    double delta = 0.0;
    if (!near.empty()) {
      Mesh rest;
      rest.V = mesh->V;
      rest.F.resize(nf - nfaces[c], 3);
      for (int f = 0, k = 0; f < nf; ++f)
        if (face_comp[f] != c) rest.F.row(k++) = mesh->F.row(f);
      MatrixX3d q(static_cast<Eigen::Index>(near.size()), 3);
      for (std::size_t j = 0; j < near.size(); ++j) q.row(static_cast<Eigen::Index>(j)) = centers.row(near[j]);
      VectorXd sq_rest;
      TriangleBvh(rest, /*oriented_boxes=*/false).ClosestPoints(q, &sq_rest);
      for (std::size_t j = 0; j < near.size(); ++j) {
        const double r = radii[near[j]];
        const double with = r - std::sqrt(sq[near[j]]), without = r - std::sqrt(sq_rest[static_cast<Eigen::Index>(j)]);
        delta += without * without - with * with;
      }
    }
    if (delta <= 0.0) {
      drop[c] = 1;
      ++st.dropped;
      st.dropped_faces += nfaces[c];
    } else {
      ++st.kept_by_fit;
    }
  }
  if (st.dropped == 0) return st;
  std::vector<int> remap(nv, -1);
  int kept_v = 0;
  for (int v = 0; v < nv; ++v)
    if (comp[v] >= 0 && !drop[comp[v]]) remap[v] = kept_v++;
  Mesh out;
  out.V.resize(kept_v, 3);
  for (int v = 0; v < nv; ++v)
    if (remap[v] >= 0) out.V.row(remap[v]) = mesh->V.row(v);
  out.F.resize(nf - st.dropped_faces, 3);
  int k = 0;
  for (int f = 0; f < nf; ++f) {
    if (drop[face_comp[f]]) continue;
    out.F.row(k++) << remap[mesh->F(f, 0)], remap[mesh->F(f, 1)], remap[mesh->F(f, 2)];
  }
  *mesh = std::move(out);
  return st;
}

}  // namespace arcs
