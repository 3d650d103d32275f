#include "framework/spatial/pseudonormal_sign.h"

#include "framework/error.h"
#include "framework/util/parallel.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>

namespace arcs {

PseudonormalSign::PseudonormalSign(const Mesh& mesh) : mesh_(&mesh) {
  const int nv = mesh.NumVertices(), nf = mesh.NumFaces();
  for (int f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k)
      if (mesh.F(f, k) < 0 || mesh.F(f, k) >= nv)
        throw InputError("", 0, "pseudonormals: face " + std::to_string(f) + " refers to vertex " +
                         std::to_string(mesh.F(f, k)) + " of " + std::to_string(nv));
  face_n_.assign(nf, Vec3::Zero());
  ParallelFor(nf, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t f = b; f < e; ++f) {
      const Vec3 a = mesh.V.row(mesh.F(f, 0)), bb = mesh.V.row(mesh.F(f, 1)), c = mesh.V.row(mesh.F(f, 2));
      const Vec3 n = (bb - a).cross(c - a);
      const double len = n.norm();
      if (len > 0 && std::isfinite(len)) face_n_[f] = n / len;
    }
  }, 4096);
  // Outgoing half-edges per vertex (the CSR lists start_ / out_).
  start_.assign(nv + 1, 0);
  out_.resize(static_cast<std::size_t>(nf) * 3);
  std::vector<int>& start = start_;
  std::vector<int>& out = out_;
  for (int f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) ++start[mesh.F(f, k) + 1];
  for (int v = 0; v < nv; ++v) start[v + 1] += start[v];
  {
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (int f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k) out[fill[mesh.F(f, k)]++] = 3 * f + k;
  }
  auto to = [&](int h) { return mesh.F(h / 3, (h % 3 + 1) % 3); };
  // The far end of each listed half-edge, beside the list: the twin search
  // below scans these contiguously instead of reading faces all over F.
  std::vector<int> out_to(out.size());
  ParallelFor(static_cast<std::int64_t>(out.size()), [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t j = b; j < e; ++j) out_to[j] = to(out[j]);
  }, 8192);
  // The twin of a -> b is the one b -> a; closed: exactly one, and no second a -> b.
  twin_of_.assign(static_cast<std::size_t>(nf) * 3, -1);
  // By vertex a: its own list (the a -> c half-edges and the duplicates
  // test) is read in order, only c's list is looked up.
  std::atomic<bool> closed{nf > 0};
  ParallelFor(nv, [&](std::int64_t b, std::int64_t e) {
    bool ok = true;
    for (std::int64_t aa = b; aa < e; ++aa) {
      const int a = static_cast<int>(aa);
      for (int i = start[a]; i < start[a + 1]; ++i) {
        const int h = out[i], c = out_to[i];
        int twins = 0, same = 0, twin = -1;
        for (int j = start[c]; j < start[c + 1]; ++j)
          if (out_to[j] == a) ++twins, twin = out[j];
        for (int j = start[a]; j < start[a + 1]; ++j) same += out_to[j] == c;
        if (twins != 1 || same != 1 || a == c) {
          ok = false;
          continue;
        }
        twin_of_[h] = twin;
      }
    }
    if (!ok) closed = false;
  }, 2048);
  closed_ = closed;
}

Vec3 PseudonormalSign::VertexNormal(int v) const {
  const Mesh& mesh = *mesh_;
  // A manifold vertex: its faces form one fan (walking from face to face
  // across the edges at v returns after all of them).
  if (start_[v + 1] > start_[v]) {
    const int first = out_[start_[v]];
    int h = first, steps = 0;
    do {
      const int prev = 3 * (h / 3) + (h % 3 + 2) % 3;  // the half-edge into v in h's face
      h = twin_of_[prev];                              // out of v in the next face
      ++steps;
    } while (h != first && h >= 0 && steps <= start_[v + 1] - start_[v]);
    if (h != first || steps != start_[v + 1] - start_[v]) return Vec3::Zero();
  }
  Vec3 s = Vec3::Zero();
  for (int j = start_[v]; j < start_[v + 1]; ++j) {
    const int h = out_[j], f = h / 3, k = h % 3;
    const Vec3 p = mesh.V.row(mesh.F(f, k)), q = mesh.V.row(mesh.F(f, (k + 1) % 3)),
               r = mesh.V.row(mesh.F(f, (k + 2) % 3));
    const Vec3 u = q - p, w = r - p;
    const double nu = u.norm(), nw = w.norm();
    if (nu == 0 || nw == 0) continue;
    const double angle = std::acos(std::clamp(u.dot(w) / (nu * nw), -1.0, 1.0));
    s += angle * face_n_[f];
  }
  return s;
}

int PseudonormalSign::Side(const Vec3& q, const Vec3& p, int face) const {
  if (!closed_ || face < 0 || face >= static_cast<int>(face_n_.size())) return 0;
  const Mesh& m = *mesh_;
  const Vec3 a = m.V.row(m.F(face, 0)), b = m.V.row(m.F(face, 1)), c = m.V.row(m.F(face, 2));
  // Where on the face p lies: barycentric coordinates by sub-areas against
  // the face normal; a coordinate below a relative 1e-9 puts p on the
  // opposite edge, two put it on a vertex.
  const Vec3 n = (b - a).cross(c - a);
  const double area = n.squaredNorm();
  Vec3 pn = Vec3::Zero();
  if (area > 0) {
    const double l[3] = {n.dot((b - p).cross(c - p)) / area, n.dot((c - p).cross(a - p)) / area,
                         n.dot((a - p).cross(b - p)) / area};
    constexpr double kEps = 1e-9;
    const bool zero[3] = {l[0] < kEps, l[1] < kEps, l[2] < kEps};
    const int nz = zero[0] + zero[1] + zero[2];
    if (nz == 0) {
      pn = face_n_[face];
    } else if (nz == 1) {
      // On the edge opposite corner k: from corner k + 1 to corner k + 2.
      const int k = zero[0] ? 0 : zero[1] ? 1 : 2;
      const int h = 3 * face + (k + 1) % 3;
      pn = face_n_[face] + face_n_[twin_of_[h] / 3];
    } else {
      const int k = !zero[0] ? 0 : !zero[1] ? 1 : 2;
      pn = VertexNormal(m.F(face, k));
    }
  } else {
    return 0;  // a degenerate face: no reliable feature
  }
  const Vec3 d = q - p;
  const double s = d.dot(pn), scale = d.norm() * pn.norm();
  if (!(scale > 0) || std::abs(s) <= 1e-12 * scale) return 0;
  return s > 0 ? 1 : -1;
}

}  // namespace arcs
