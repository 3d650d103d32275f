#include "framework/points/point_utils.h"

#include "framework/error.h"
#include "framework/geometry/submesh.h"

#include <Eigen/Geometry>
#include "framework/spatial/knn.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <vector>

namespace arcs {

double PointSpacing(const MatrixX3d& P) {
  const int n = static_cast<int>(P.rows());
  if (n < 2) throw Error("point spacing: needs at least 2 points, got " + std::to_string(n));
  KdTree3 tree(P);
  const int m = std::min(n, 4096);
  double sum = 0.0;
  int count = 0;
  for (int s = 0; s < m; ++s) {
    const int i = static_cast<int>(static_cast<std::int64_t>(s) * n / m);
    std::vector<double> d2;
    // A few neighbours: coincident copies of the point itself come first.
    const std::vector<int> nn = tree.Knn(P.row(i).transpose(), 8, &d2);
    for (size_t j = 0; j < nn.size(); ++j) {
      if (d2[j] > 0.0) {
        sum += std::sqrt(d2[j]);
        ++count;
        break;
      }
    }
  }
  if (count == 0) throw Error("point spacing: all points coincide");
  return sum / count;
}

PreparedPoints PrepareReconstructionInput(const PointCloud& in, const std::string& who, bool need_normals,
                                          int min_points) {
  const int n = in.Size();
  if (n < min_points)
    throw Error(who + ": needs at least " + std::to_string(min_points) + " points, got " + std::to_string(n));
  bool use_normals = in.HasNormals();
  if (need_normals && !use_normals)
    throw Error(who + ": needs oriented points (normals), the cloud has none: add estimate_normals to the input pipeline");
  for (int i = 0; i < n; ++i)
    if (!in.P.row(i).allFinite())
      throw Error(who + ": point " + std::to_string(i) + " has a non-finite coordinate");
  if (use_normals) {
    for (int i = 0; i < n; ++i) {
      const double len = in.N.row(i).norm();
      if (!std::isfinite(len) || len == 0.0) {
        if (need_normals)
          throw Error(who + ": point " + std::to_string(i) + " has a " + (std::isfinite(len) ? "zero" : "non-finite") +
                      " normal");
        use_normals = false;  // optional normals: ignore an unusable set
        break;
      }
    }
  }
  // Exact duplicates: sort rows lexicographically, keep the first occurrence.
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  auto less = [&](int a, int b) {
    for (int k = 0; k < 3; ++k)
      if (in.P(a, k) != in.P(b, k)) return in.P(a, k) < in.P(b, k);
    return a < b;
  };
  std::sort(order.begin(), order.end(), less);
  std::vector<char> keep(n, 1);
  for (int j = 1; j < n; ++j)
    if (in.P.row(order[j]) == in.P.row(order[j - 1])) keep[order[j]] = 0;
  PreparedPoints out;
  const int kept = static_cast<int>(std::count(keep.begin(), keep.end(), 1));
  out.duplicates_removed = n - kept;
  if (kept < min_points)
    throw Error(who + ": needs at least " + std::to_string(min_points) + " distinct points, got " +
                std::to_string(kept) + " (" + std::to_string(out.duplicates_removed) + " duplicates)");
  out.cloud.P.resize(kept, 3);
  if (use_normals) out.cloud.N.resize(kept, 3);
  for (int i = 0, r = 0; i < n; ++i) {
    if (!keep[i]) continue;
    out.cloud.P.row(r) = in.P.row(i);
    if (use_normals) out.cloud.N.row(r) = in.N.row(i).normalized();
    ++r;
  }
  return out;
}

namespace {
int Find(std::vector<int>& parent, int x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}
}  // namespace

int OrientComponents(Mesh* mesh, const MatrixX3d* vertex_normals) {
  const int nv = mesh->NumVertices(), nf = mesh->NumFaces();
  std::vector<int> parent(nv);
  std::iota(parent.begin(), parent.end(), 0);
  for (int f = 0; f < nf; ++f)
    for (int k = 1; k < 3; ++k) {
      const int a = Find(parent, mesh->F(f, 0)), b = Find(parent, mesh->F(f, k));
      if (a != b) parent[a] = b;
    }
  // Per component: signed volume, normal agreement, and directed-edge balance
  // (closed <=> every directed edge has its reverse).
  struct Acc {
    double volume = 0, agree = 0;
    std::vector<std::array<int, 2>> edges;
  };
  std::vector<int> comp_of_root(nv, -1);
  std::vector<Acc> acc;
  std::vector<int> face_comp(nf);
  for (int f = 0; f < nf; ++f) {
    const int r = Find(parent, mesh->F(f, 0));
    if (comp_of_root[r] < 0) {
      comp_of_root[r] = static_cast<int>(acc.size());
      acc.emplace_back();
    }
    const int c = comp_of_root[r];
    face_comp[f] = c;
    const Vec3 a = mesh->V.row(mesh->F(f, 0)), b = mesh->V.row(mesh->F(f, 1)), d = mesh->V.row(mesh->F(f, 2));
    const Vec3 n2 = (b - a).cross(d - a);  // twice the area times the unit normal
    acc[c].volume += a.dot(b.cross(d)) / 6.0;
    if (vertex_normals) {
      const Vec3 vn = vertex_normals->row(mesh->F(f, 0)) + vertex_normals->row(mesh->F(f, 1)) +
                      vertex_normals->row(mesh->F(f, 2));
      if (vn.norm() > 0) acc[c].agree += n2.dot(vn.normalized());
    }
    for (int k = 0; k < 3; ++k) acc[c].edges.push_back({mesh->F(f, k), mesh->F(f, (k + 1) % 3)});
  }
  std::vector<char> flip(acc.size(), 0);
  int flipped = 0;
  for (size_t c = 0; c < acc.size(); ++c) {
    auto& e = acc[c].edges;
    std::sort(e.begin(), e.end());
    bool closed = true;
    for (const auto& d : e)
      if (!std::binary_search(e.begin(), e.end(), std::array<int, 2>{d[1], d[0]})) {
        closed = false;
        break;
      }
    if (closed) {
      flip[c] = acc[c].volume < 0;
    } else if (vertex_normals) {
      flip[c] = acc[c].agree < 0;
    }
    flipped += flip[c];
  }
  for (int f = 0; f < nf; ++f)
    if (flip[face_comp[f]]) std::swap(mesh->F(f, 1), mesh->F(f, 2));
  return flipped;
}

Mesh CompactMesh(const Mesh& mesh) {
  std::vector<char> keep(mesh.NumFaces());
  for (int f = 0; f < mesh.NumFaces(); ++f) {
    const int a = mesh.F(f, 0), b = mesh.F(f, 1), c = mesh.F(f, 2);
    keep[f] = a != b && b != c && a != c;
  }
  return KeepFaces(mesh, keep);
}

}  // namespace arcs
