#include "framework/geometry/submesh.h"

#include "framework/error.h"

#include <string>

namespace arcs {

Mesh KeepFaces(const Mesh& mesh, const std::vector<char>& keep) {
  const int nv = mesh.NumVertices(), nf = mesh.NumFaces();
  if (static_cast<int>(keep.size()) != nf)
    throw Error("KeepFaces: " + std::to_string(keep.size()) + " flags for " + std::to_string(nf) + " faces");
  std::vector<int> remap(nv, -1);
  int kept_f = 0;
  for (int f = 0; f < nf; ++f) {
    if (!keep[f]) continue;
    ++kept_f;
    for (int k = 0; k < 3; ++k) remap[mesh.F(f, k)] = 0;
  }
  int kept_v = 0;
  for (int v = 0; v < nv; ++v)
    if (remap[v] == 0) remap[v] = kept_v++;
  Mesh out;
  out.V.resize(kept_v, 3);
  for (int v = 0; v < nv; ++v)
    if (remap[v] >= 0) out.V.row(remap[v]) = mesh.V.row(v);
  out.F.resize(kept_f, 3);
  int i = 0;
  for (int f = 0; f < nf; ++f)
    if (keep[f]) out.F.row(i++) << remap[mesh.F(f, 0)], remap[mesh.F(f, 1)], remap[mesh.F(f, 2)];
  return out;
}

}  // namespace arcs
