// An out-of-tree reconstructor plugin: the convex hull of the points, a
// legitimate (if crude) point-cloud -> mesh method and a lower bound of what
// any reconstructor should beat on non-convex shapes. Built against the
// *installed* arcs headers (find_package(arcs) -> arcs::plugin_api), loaded
// at run time with `arcs run --plugin libarcs_convex_hull.so EXP.yaml`.
//
// Algorithm: incremental hull (Clarkson & Shor style without conflict
// lists): start from a non-degenerate tetrahedron, insert each point outside
// the current hull by removing the faces it sees and coning the horizon to
// it. O(n * #faces); fine for clouds of a few 10k points.
#include "registry/bind.h"
#include "registry/plugin_api.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <vector>

namespace {

using arcs::Mesh;
using arcs::PointCloud;
using arcs::Vec3;

struct Face {
  std::array<int, 3> v;
  Vec3 n;      // outward, unnormalised
  bool alive;
};

Face MakeFace(const arcs::MatrixX3d& P, int a, int b, int c) {
  const Vec3 pa = P.row(a), pb = P.row(b), pc = P.row(c);
  return {{a, b, c}, (pb - pa).cross(pc - pa), true};
}

// Convex hull of the rows of P, faces wound outward; vertices = hull points
// only. Throws arcs::Error on fewer than 4 points or points spanning no volume.
Mesh ConvexHull(const arcs::MatrixX3d& P, double rel_eps) {
  const int n = static_cast<int>(P.rows());
  if (n < 4) throw arcs::Error("convex_hull: needs at least 4 points, got " + std::to_string(n));
  const Vec3 lo = P.colwise().minCoeff(), hi = P.colwise().maxCoeff();
  const double scale = (hi - lo).norm();
  if (!std::isfinite(scale)) throw arcs::Error("convex_hull: non-finite coordinates");
  const double eps = rel_eps * scale;
  // Initial tetrahedron: two far-apart points, the point farthest from
  // their line, the point farthest from their plane.
  int i0 = 0, i1 = 0;
  for (int i = 0; i < n; ++i) {
    if (P(i, 0) < P(i0, 0)) i0 = i;
    if (P(i, 0) > P(i1, 0)) i1 = i;
  }
  if (i0 == i1) {  // all x equal: pick along y / z
    for (int i = 0; i < n; ++i)
      if ((P.row(i) - P.row(i0)).norm() > (P.row(i1) - P.row(i0)).norm()) i1 = i;
  }
  const Vec3 a = P.row(i0), d = (Vec3(P.row(i1)) - a).normalized();
  int i2 = -1;
  double best = eps;
  for (int i = 0; i < n; ++i) {
    const Vec3 w = Vec3(P.row(i)) - a;
    const double dist = (w - w.dot(d) * d).norm();
    if (dist > best) best = dist, i2 = i;
  }
  if (i2 < 0) throw arcs::Error("convex_hull: the points are collinear");
  const Vec3 pn = (Vec3(P.row(i1)) - a).cross(Vec3(P.row(i2)) - a).normalized();
  int i3 = -1;
  best = eps;
  for (int i = 0; i < n; ++i) {
    const double dist = std::abs((Vec3(P.row(i)) - a).dot(pn));
    if (dist > best) best = dist, i3 = i;
  }
  if (i3 < 0) throw arcs::Error("convex_hull: the points are coplanar (no volume)");
  std::vector<Face> faces;
  if ((Vec3(P.row(i3)) - a).dot(pn) > 0) std::swap(i1, i2);  // i3 behind face (i0, i1, i2)
  faces.push_back(MakeFace(P, i0, i1, i2));
  faces.push_back(MakeFace(P, i0, i3, i1));
  faces.push_back(MakeFace(P, i1, i3, i2));
  faces.push_back(MakeFace(P, i2, i3, i0));
  for (int p = 0; p < n; ++p) {
    if (p == i0 || p == i1 || p == i2 || p == i3) continue;
    const Vec3 q = P.row(p);
    std::set<std::pair<int, int>> visible_edges;
    std::vector<int> visible;
    for (int f = 0; f < static_cast<int>(faces.size()); ++f) {
      if (!faces[f].alive) continue;
      const Face& F = faces[f];
      if (F.n.dot(q - Vec3(P.row(F.v[0]))) > eps * F.n.norm()) visible.push_back(f);
    }
    if (visible.empty()) continue;  // inside (or on) the hull
    for (int f : visible) {
      faces[f].alive = false;
      for (int k = 0; k < 3; ++k) visible_edges.insert({faces[f].v[k], faces[f].v[(k + 1) % 3]});
    }
    // Horizon: edges of the visible region whose reverse is not visible.
    for (const auto& [u, v] : visible_edges)
      if (!visible_edges.count({v, u})) faces.push_back(MakeFace(P, u, v, p));
    if (faces.size() > 8 * static_cast<size_t>(n) + 64) {  // compact dead faces now and then
      faces.erase(std::remove_if(faces.begin(), faces.end(), [](const Face& f) { return !f.alive; }), faces.end());
    }
  }
  std::map<int, int> remap;
  std::vector<std::array<int, 3>> out;
  for (const Face& f : faces)
    if (f.alive) {
      out.push_back(f.v);
      for (int v : f.v) remap.emplace(v, 0);
    }
  Mesh m;
  m.V.resize(static_cast<int>(remap.size()), 3);
  int next = 0;
  for (auto& [old, idx] : remap) {
    idx = next;
    m.V.row(next++) = P.row(old);
  }
  m.F.resize(static_cast<int>(out.size()), 3);
  for (int f = 0; f < static_cast<int>(out.size()); ++f)
    for (int k = 0; k < 3; ++k) m.F(f, k) = remap[out[f][k]];
  return m;
}

struct HullOptions {
  double epsilon = 1e-10;  // visibility tolerance, relative to the bounding-box diagonal
  void Check() const {
    ARCS_CHECK_OPTION(epsilon >= 0.0 && epsilon <= 1e-2, "epsilon", epsilon, "in [0, 0.01]");
  }
};

// The stage body: the contract (reads points, writes output) guarantees d.points.
void RunConvexHull(arcs::Context&, arcs::CaseData& d, const HullOptions& o, const arcs::ParamMap&) {
  if (d.points->Size() == 0) throw arcs::Error("the point cloud is empty");
  d.output = ConvexHull(d.points->P, o.epsilon);
  d.SetMetric("hull_vertices", d.output->NumVertices());
}

void Register(arcs::Registry& r) {
  arcs::StageInfo s = arcs::DeclareStage("convex_hull", arcs::Role::kReconstructor,
                                         "convex hull of the points (out-of-tree example plugin; normals unused)",
                                         {arcs::Slot::kPoints}, {arcs::Slot::kOutput}, arcs::k3D);
  arcs::BindStage<HullOptions>(
      s,
      arcs::Binder<HullOptions>().Double("epsilon", &HullOptions::epsilon,
                                         "visibility tolerance, relative to the bounding-box diagonal",
                                         arcs::Closed(0.0, 1e-2)),
      RunConvexHull);
  s.outputs = {"hull_vertices"};
  r.Register(std::move(s));
}

}  // namespace

ARCS_PLUGIN("convex_hull", "1.0", Register)
