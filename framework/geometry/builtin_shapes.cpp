#include "framework/geometry/builtin_shapes.h"

#include "framework/error.h"

#include <Eigen/Geometry>

#include <cmath>
#include <map>
#include <utility>

namespace arcs {

Mesh MakeIcosphere(double radius, int subdivisions, const Vec3& center) {
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
      auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back((v[a] + v[b]).normalized());
      const int idx = static_cast<int>(v.size()) - 1;
      mid.emplace(key, idx);
      return idx;
    };
    std::vector<std::array<int, 3>> nf;
    nf.reserve(f.size() * 4);
    for (const auto& tri : f) {
      const int a = midpoint(tri[0], tri[1]), b = midpoint(tri[1], tri[2]), c = midpoint(tri[2], tri[0]);
      nf.push_back({tri[0], a, c});
      nf.push_back({tri[1], b, a});
      nf.push_back({tri[2], c, b});
      nf.push_back({a, b, c});
    }
    f = std::move(nf);
  }
  Mesh m;
  m.V.resize(static_cast<Eigen::Index>(v.size()), 3);
  for (size_t i = 0; i < v.size(); ++i) m.V.row(static_cast<Eigen::Index>(i)) = (center + radius * v[i]).transpose();
  m.F.resize(static_cast<Eigen::Index>(f.size()), 3);
  for (size_t i = 0; i < f.size(); ++i)
    m.F.row(static_cast<Eigen::Index>(i)) << f[i][0], f[i][1], f[i][2];
  return m;
}

namespace {
// A closed tube around a closed centre curve given by `curve(u)` (u in
// [0,1)), with a frame from `frame(u)` returning two unit normals.
template <typename Curve, typename Frame>
Mesh Tube(int nu, int nv, double r, Curve curve, Frame frame) {
  Mesh m;
  m.V.resize(static_cast<Eigen::Index>(nu) * nv, 3);
  m.F.resize(static_cast<Eigen::Index>(nu) * nv * 2, 3);
  for (int i = 0; i < nu; ++i) {
    const double u = static_cast<double>(i) / nu;
    const Vec3 c = curve(u);
    const auto [n1, n2] = frame(u);
    for (int j = 0; j < nv; ++j) {
      const double phi = 2.0 * M_PI * j / nv;
      m.V.row(i * nv + j) = (c + r * (std::cos(phi) * n1 + std::sin(phi) * n2)).transpose();
    }
  }
  int k = 0;
  for (int i = 0; i < nu; ++i) {
    const int i1 = (i + 1) % nu;
    for (int j = 0; j < nv; ++j) {
      const int j1 = (j + 1) % nv;
      const int a = i * nv + j, b = i1 * nv + j, c = i1 * nv + j1, d = i * nv + j1;
      m.F.row(k++) << a, b, c;
      m.F.row(k++) << a, c, d;
    }
  }
  return m;
}

// Fixes orientation so the signed volume is positive.
void OrientOutward(Mesh* m) {
  double vol = 0;
  for (int f = 0; f < m->NumFaces(); ++f) {
    const Vec3 a = m->V.row(m->F(f, 0)), b = m->V.row(m->F(f, 1)), c = m->V.row(m->F(f, 2));
    vol += a.dot(b.cross(c));
  }
  if (vol < 0)
    for (int f = 0; f < m->NumFaces(); ++f) std::swap(m->F(f, 1), m->F(f, 2));
}
}  // namespace

Mesh MakeTorus(double R, double r, int nu, int nv) {
  Mesh m = Tube(nu, nv, r,
                [&](double u) { return Vec3(R * std::cos(2 * M_PI * u), R * std::sin(2 * M_PI * u), 0.0); },
                [&](double u) {
                  return std::make_pair(Vec3(std::cos(2 * M_PI * u), std::sin(2 * M_PI * u), 0.0), Vec3(0, 0, 1));
                });
  OrientOutward(&m);
  return m;
}

Mesh MakeTorusKnot(int p, int q, double R, double a, double r, int nu, int nv) {
  auto curve = [=](double u) {
    const double t = 2 * M_PI * u;
    const double rr = R + a * std::cos(q * t);
    return Vec3(rr * std::cos(p * t), rr * std::sin(p * t), a * std::sin(q * t));
  };
  // Frame: tangent by central difference, normals by projecting a fixed-ish
  // axis (the curve's position direction), which never aligns with the tangent here.
  auto frame = [=](double u) {
    const double h = 1e-5;
    const Vec3 tan = (curve(u + h) - curve(u - h)).normalized();
    Vec3 ref = curve(u);
    ref.z() = 0;
    Vec3 n1 = (ref - ref.dot(tan) * tan).normalized();
    Vec3 n2 = tan.cross(n1);
    return std::make_pair(n1, n2);
  };
  Mesh m = Tube(nu, nv, r, curve, frame);
  OrientOutward(&m);
  return m;
}

Mesh Concatenate(const std::vector<Mesh>& parts) {
  Mesh out;
  Eigen::Index nv = 0, nf = 0;
  for (const auto& p : parts) nv += p.V.rows(), nf += p.F.rows();
  out.V.resize(nv, 3);
  out.F.resize(nf, 3);
  Eigen::Index v0 = 0, f0 = 0;
  for (const auto& p : parts) {
    out.V.middleRows(v0, p.V.rows()) = p.V;
    out.F.middleRows(f0, p.F.rows()) = p.F.array() + static_cast<int>(v0);
    v0 += p.V.rows(), f0 += p.F.rows();
  }
  return out;
}

std::vector<std::string> BuiltinShapeNames() { return {"sphere", "torus", "knot", "two_tori"}; }

Mesh MakeBuiltinShape(const std::string& name) {
  if (name == "sphere") return MakeIcosphere(0.5, 5);
  if (name == "torus") return MakeTorus();
  if (name == "knot") return MakeTorusKnot();
  if (name == "two_tori") {
    Mesh a = MakeTorus(0.25, 0.1, 200, 100), b = MakeTorus(0.25, 0.1, 200, 100);
    a.V.col(0).array() -= 0.4;
    b.V.col(0).array() += 0.4;
    // b stands upright (rotated 90 degrees about x); the two do not touch.
    for (int i = 0; i < b.NumVertices(); ++i) {
      const double y = b.V(i, 1), z = b.V(i, 2);
      b.V(i, 1) = -z, b.V(i, 2) = y;
    }
    return Concatenate({a, b});
  }
  std::string valid;
  for (const auto& n : BuiltinShapeNames()) valid += (valid.empty() ? "" : ", ") + n;
  throw Error("unknown built-in shape '" + name + "'; valid: " + valid);
}

}  // namespace arcs
