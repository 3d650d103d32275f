#include "framework/sdfmesh/power_diagram.h"

#include "framework/error.h"
#include "framework/sdfmesh/backends.h"
#include "framework/sdfmesh/sdf_input.h"
#include "framework/util/parallel.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace arcs {

bool PowerDiagramAvailable() { return sdfmesh_detail::CgalAvailable(); }

void PowerDiagramOptions::Check() const {
  if (!std::isfinite(isovalue)) throw OptionError("isovalue = " + std::to_string(isovalue) + ": must be finite");
}

Mesh PowerDiagramContour(const SdfSamples& s, const PowerDiagramOptions& o, PowerDiagramStats* stats) {
  o.Check();
  CheckSdfToMeshInput(s, "power_diagram", /*need_grid=*/false, o.isovalue);
  if (s.Size() > 2000000000) throw Error("power_diagram: more than 2e9 samples are not supported");
  const std::int64_t n = s.Size();
  VectorXd w(n);
  std::vector<std::uint8_t> inside(n);
  for (std::int64_t i = 0; i < n; ++i) {
    w[i] = o.weighted ? s.values[i] * s.values[i] : 0.0;
    inside[i] = s.values[i] < o.isovalue;
  }
  std::int64_t num_vertices = 0, num_tets = 0;
  int dimension = 0;
  const std::vector<std::array<int, 4>> tets =
      sdfmesh_detail::RegularTetrahedraCrossing(s.points, w, inside, &num_vertices, &num_tets, &dimension);
  if (dimension < 3)
    throw Error("power_diagram: the samples span no volume (the triangulation has dimension " +
                std::to_string(dimension) + ")");
  if (tets.empty())
    throw Error("power_diagram: no tetrahedron of the " + std::string(o.weighted ? "regular" : "Delaunay") +
                " triangulation has vertices of both signs (the weights hide every sample of one sign)");

  using EdgeKey = std::pair<int, int>;  // (inside sample, outside sample)
  auto pos = [&](int i) { return Vec3(s.points(i, 0), s.points(i, 1), s.points(i, 2)); };
  auto edge_point = [&](const EdgeKey& e) {
    const Vec3 a = pos(e.first), b = pos(e.second);
    const double sa = s.values[e.first] - o.isovalue, sb = s.values[e.second] - o.isovalue;  // sa < 0 <= sb
    double t = sa / (sa - sb);
    if (o.vertex == PowerDiagramOptions::Vertex::kSphereGap) {
      const double len = (b - a).norm();
      const double ra = std::abs(s.values[e.first]), rb = std::abs(s.values[e.second]);
      if (len > 0 && ra + rb <= len) t = 0.5 * (ra + (len - rb)) / len;
    }
    return Vec3(a + std::clamp(t, 0.0, 1.0) * (b - a));
  };

  // Marching tetrahedra: triangles as edge keys, wound outward (towards the
  // outside vertices' side), per tetrahedron in parallel.
  using Tri = std::array<EdgeKey, 3>;
  std::vector<std::array<Tri, 2>> per_tet(tets.size());
  std::vector<std::uint8_t> count(tets.size(), 0);
  ParallelFor(static_cast<std::int64_t>(tets.size()), [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t ti = b; ti < e; ++ti) {
      std::array<int, 4> in{}, out{};
      int ni = 0, no = 0;
      for (int v : tets[ti]) (inside[v] ? in[ni++] : out[no++]) = v;
      Vec3 dir = Vec3::Zero();
      for (int k = 0; k < no; ++k) dir += pos(out[k]) / no;
      for (int k = 0; k < ni; ++k) dir -= pos(in[k]) / ni;
      auto emit = [&](Tri t) {
        const Vec3 p0 = edge_point(t[0]), p1 = edge_point(t[1]), p2 = edge_point(t[2]);
        if ((p1 - p0).cross(p2 - p0).dot(dir) < 0) std::swap(t[1], t[2]);
        per_tet[ti][count[ti]++] = t;
      };
      if (ni == 1) {
        emit({EdgeKey{in[0], out[0]}, EdgeKey{in[0], out[1]}, EdgeKey{in[0], out[2]}});
      } else if (no == 1) {
        emit({EdgeKey{in[0], out[0]}, EdgeKey{in[1], out[0]}, EdgeKey{in[2], out[0]}});
      } else {  // two and two: the quad (a c, a d, b d, b c), split along the shorter diagonal
        const EdgeKey ac{in[0], out[0]}, ad{in[0], out[1]}, bd{in[1], out[1]}, bc{in[1], out[0]};
        if ((edge_point(ac) - edge_point(bd)).squaredNorm() <= (edge_point(ad) - edge_point(bc)).squaredNorm()) {
          emit({ac, ad, bd});
          emit({ac, bd, bc});
        } else {
          emit({ac, ad, bc});
          emit({ad, bd, bc});
        }
      }
    }
  }, 4096);
  // Canonical order: vertices by edge key, faces by their (rotated) keys.
  std::vector<EdgeKey> keys;
  keys.reserve(4 * tets.size());
  for (size_t ti = 0; ti < tets.size(); ++ti)
    for (int k = 0; k < count[ti]; ++k)
      for (const auto& e : per_tet[ti][k]) keys.push_back(e);
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  auto vid = [&](const EdgeKey& e) {
    return static_cast<int>(std::lower_bound(keys.begin(), keys.end(), e) - keys.begin());
  };
  std::vector<std::array<int, 3>> faces;
  faces.reserve(2 * tets.size());
  for (size_t ti = 0; ti < tets.size(); ++ti)
    for (int k = 0; k < count[ti]; ++k) {
      const Tri& t = per_tet[ti][k];
      std::array<int, 3> f{vid(t[0]), vid(t[1]), vid(t[2])};
      std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
      faces.push_back(f);
    }
  std::sort(faces.begin(), faces.end());
  Mesh m;
  m.V.resize(static_cast<Eigen::Index>(keys.size()), 3);
  ParallelFor(static_cast<std::int64_t>(keys.size()), [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t i = b; i < e; ++i) m.V.row(i) = edge_point(keys[i]).transpose();
  }, 4096);
  m.F.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (size_t i = 0; i < faces.size(); ++i) m.F.row(i) << faces[i][0], faces[i][1], faces[i][2];
  if (stats) {
    stats->hidden = n - num_vertices;
    stats->tetrahedra = num_tets;
    stats->crossed = static_cast<std::int64_t>(tets.size());
  }
  return m;
}

}  // namespace arcs
