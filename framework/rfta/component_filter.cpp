#include "framework/rfta/component_filter.h"

#include "framework/rfta/sphere_set.h"
#include "framework/rfta/sphere_tree.h"
#include "framework/spatial/topology.h"
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
  const SphereTree tree(centers, radii, ids);
  std::vector<char> inside(nv, 0);
  ParallelFor(nv, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t v = b; v < e; ++v)
      if (comp[v] >= 0) inside[v] = tree.AnyContains(mesh->V.row(v).transpose(), -tol, -1);
  });
  std::vector<int> nverts(nc, 0), ninside(nc, 0), nfaces(nc, 0);
  for (int v = 0; v < nv; ++v) {
    if (comp[v] < 0) continue;
    ++nverts[comp[v]];
    ninside[comp[v]] += inside[v];
  }
  for (int f = 0; f < nf; ++f) ++nfaces[face_comp[f]];
  const int largest = static_cast<int>(std::max_element(nfaces.begin(), nfaces.end()) - nfaces.begin());
  std::vector<char> drop(nc, 0);
  for (int c = 0; c < nc; ++c) {
    if (c == largest) continue;
    if (ninside[c] > max_inside_fraction * nverts[c]) {
      drop[c] = 1;
      ++st.dropped;
      st.dropped_faces += nfaces[c];
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
