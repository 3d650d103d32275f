// Meshes generated for the spatial tests (icosphere, torus, ...) and a minimal
// OBJ reader (v/f lines only; the io module is tested on its own).
#pragma once

#include "framework/types.h"

#include <Eigen/Geometry>

#include <array>

#include <cmath>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace arcs::spatial_test {

// Signed volume (divergence theorem); used to fix the orientation outward.
inline double SignedVolume(const Mesh& m) {
  double v = 0.0;
  for (int f = 0; f < m.NumFaces(); ++f) {
    const Vec3 a = m.V.row(m.F(f, 0)), b = m.V.row(m.F(f, 1)), c = m.V.row(m.F(f, 2));
    v += a.dot(b.cross(c)) / 6.0;
  }
  return v;
}

inline void FlipIfInward(Mesh* m) {
  if (SignedVolume(*m) < 0.0) m->F.col(1).swap(m->F.col(2));
}

// Subdivided icosahedron projected to the sphere of `radius` about `centre`.
inline Mesh Icosphere(int subdivisions, double radius = 1.0, const Vec3& centre = Vec3::Zero()) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                         {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<int, 3>> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                       {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                       {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                       {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (auto& p : v) p.normalize();
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back((v[a] + v[b]).normalized());
      return mid[key] = static_cast<int>(v.size()) - 1;
    };
    std::vector<std::array<int, 3>> nf;
    for (const auto& tri : f) {
      const int a = midpoint(tri[0], tri[1]), b = midpoint(tri[1], tri[2]), c = midpoint(tri[2], tri[0]);
      nf.push_back({tri[0], a, c});
      nf.push_back({tri[1], b, a});
      nf.push_back({tri[2], c, b});
      nf.push_back({a, b, c});
    }
    f.swap(nf);
  }
  Mesh m;
  m.V.resize(v.size(), 3);
  for (std::size_t i = 0; i < v.size(); ++i) m.V.row(i) = (centre + radius * v[i]).transpose();
  m.F.resize(f.size(), 3);
  for (std::size_t i = 0; i < f.size(); ++i) m.F.row(i) << f[i][0], f[i][1], f[i][2];
  FlipIfInward(&m);
  return m;
}

// Torus around the z axis: major radius R, minor radius r, nu x nv quads split in two.
inline Mesh Torus(double R, double r, int nu, int nv, const Vec3& centre = Vec3::Zero()) {
  Mesh m;
  m.V.resize(nu * nv, 3);
  for (int i = 0; i < nu; ++i) {
    const double u = 2.0 * std::numbers::pi * i / nu;
    for (int j = 0; j < nv; ++j) {
      const double w = 2.0 * std::numbers::pi * j / nv;
      m.V.row(i * nv + j) = (centre + Vec3((R + r * std::cos(w)) * std::cos(u),
                                           (R + r * std::cos(w)) * std::sin(u), r * std::sin(w)))
                                .transpose();
    }
  }
  m.F.resize(2 * nu * nv, 3);
  int k = 0;
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      const int a = i * nv + j, b = ((i + 1) % nu) * nv + j, c = ((i + 1) % nu) * nv + (j + 1) % nv,
                d = i * nv + (j + 1) % nv;
      m.F.row(k++) << a, b, c;
      m.F.row(k++) << a, c, d;
    }
  }
  FlipIfInward(&m);
  return m;
}

// Concatenation of two meshes.
inline Mesh Concat(const Mesh& a, const Mesh& b) {
  Mesh m;
  m.V.resize(a.V.rows() + b.V.rows(), 3);
  m.V << a.V, b.V;
  m.F.resize(a.F.rows() + b.F.rows(), 3);
  m.F << a.F, (b.F.array() + a.NumVertices()).matrix();
  return m;
}

// Minimal OBJ reader: `v x y z` and `f i j k ...` (fan-triangulated; v/vt/vn
// tokens and negative indices accepted). Throws std::runtime_error.
inline Mesh ReadObjVF(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  std::vector<double> v;
  std::vector<int> f;
  std::string line;
  while (std::getline(in, line)) {
    if (line.size() < 2) continue;
    if (line[0] == 'v' && (line[1] == ' ' || line[1] == '\t')) {
      std::istringstream s(line.substr(2));
      double x, y, z;
      s >> x >> y >> z;
      v.insert(v.end(), {x, y, z});
    } else if (line[0] == 'f' && (line[1] == ' ' || line[1] == '\t')) {
      std::istringstream s(line.substr(2));
      std::string tok;
      std::vector<int> poly;
      const int nv = static_cast<int>(v.size() / 3);
      while (s >> tok) {
        const int i = std::stoi(tok.substr(0, tok.find('/')));
        poly.push_back(i < 0 ? nv + i : i - 1);
      }
      for (std::size_t k = 1; k + 1 < poly.size(); ++k) f.insert(f.end(), {poly[0], poly[k], poly[k + 1]});
    }
  }
  Mesh m;
  m.V = Eigen::Map<MatrixX3d>(v.data(), v.size() / 3, 3);
  m.F = Eigen::Map<MatrixX3i>(f.data(), f.size() / 3, 3);
  return m;
}

// Rows of a tab-separated MANIFEST: header name -> value, one map per line.
inline std::vector<std::map<std::string, std::string>> ReadManifest(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::map<std::string, std::string>> rows;
  std::string line;
  std::vector<std::string> header;
  auto split = [](const std::string& l) {
    std::vector<std::string> out;
    std::size_t s = 0;
    for (;;) {
      const std::size_t e = l.find('\t', s);
      out.push_back(l.substr(s, e == std::string::npos ? std::string::npos : e - s));
      if (e == std::string::npos) break;
      s = e + 1;
    }
    return out;
  };
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    const auto cells = split(line);
    if (header.empty()) {
      header = cells;
      continue;
    }
    std::map<std::string, std::string> row;
    for (std::size_t i = 0; i < cells.size() && i < header.size(); ++i) row[header[i]] = cells[i];
    rows.push_back(row);
  }
  return rows;
}

// Regular grid of n^3 nodes over the cube [lo, hi]^3, x fastest.
inline MatrixX3d GridPoints(int n, double lo, double hi) {
  MatrixX3d Q(static_cast<std::int64_t>(n) * n * n, 3);
  std::int64_t r = 0;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        Q.row(r++) << lo + (hi - lo) * i / (n - 1), lo + (hi - lo) * j / (n - 1),
            lo + (hi - lo) * k / (n - 1);
  return Q;
}

// Scales so the longest bounding-box side is 1 and centres the box at 0.
inline void NormalizeUnitBox(Mesh* m) {
  const Vec3 lo = m->V.colwise().minCoeff().transpose(), hi = m->V.colwise().maxCoeff().transpose();
  const Vec3 c = 0.5 * (lo + hi);
  const double s = 1.0 / (hi - lo).maxCoeff();
  for (int i = 0; i < m->NumVertices(); ++i) m->V.row(i) = ((m->V.row(i).transpose() - c) * s).transpose();
}

}  // namespace arcs::spatial_test
