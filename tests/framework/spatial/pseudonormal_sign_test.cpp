// The pseudonormal inside test (pseudonormal_sign.h) against the exact
// winding number: on closed meshes with smooth parts, sharp edges and
// corners, every decided answer agrees, at random points near and far and at
// points whose closest feature is an edge or a vertex; open meshes and
// non-manifold vertices are undecided, never wrong.
#include "framework/spatial/pseudonormal_sign.h"

#include "framework/error.h"
#include "framework/spatial/triangle_bvh.h"
#include "framework/spatial/winding_number.h"
#include "framework/util/rng.h"
#include "tests/framework/spatial/spatial_test_meshes.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

namespace arcs {
namespace {

// The unit cube [0,1]^3, 12 outward triangles: every closest feature kind.
Mesh Cube(const Vec3& at = Vec3::Zero()) {
  Mesh m;
  m.V.resize(8, 3);
  for (int i = 0; i < 8; ++i) m.V.row(i) = (at + Vec3(i & 1, (i >> 1) & 1, (i >> 2) & 1)).transpose();
  m.F.resize(12, 3);
  m.F << 0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5;
  return m;
}

// Counts (agree, undecided) over the points, asserting no decided answer
// disagrees with the exact winding number.
std::pair<int, int> Check(const Mesh& m, const std::vector<Vec3>& pts) {
  const PseudonormalSign sign(m);
  const TriangleBvh bvh(m);
  int agree = 0, undecided = 0;
  for (const Vec3& q : pts) {
    const TriangleBvh::Hit h = bvh.Closest(q);
    const int side = sign.Side(q, h.point, h.face);
    if (side == 0) {
      ++undecided;
      continue;
    }
    const bool inside = WindingNumberExact(m, q) > 0.5;
    EXPECT_EQ(side < 0, inside) << "q = " << q.transpose() << ", closest " << h.point.transpose();
    agree += (side < 0) == inside;
  }
  return {agree, undecided};
}

std::vector<Vec3> Random(int n, const Vec3& lo, const Vec3& hi, std::uint64_t seed) {
  Rng rng(seed);
  std::vector<Vec3> p;
  for (int i = 0; i < n; ++i)
    p.push_back(lo + (hi - lo).cwiseProduct(Vec3(rng.Uniform(), rng.Uniform(), rng.Uniform())));
  return p;
}

TEST(PseudonormalSign, CubeCornersAndEdgesAgreeWithTheWindingNumber) {
  const Mesh cube = Cube();
  const PseudonormalSign sign(cube);
  EXPECT_TRUE(sign.closed());
  std::vector<Vec3> pts = Random(4000, Vec3::Constant(-0.5), Vec3::Constant(1.5), 3);
  // Points whose closest feature is a corner or an edge, from outside and inside.
  Rng rng(5);
  for (int c = 0; c < 8; ++c) {
    const Vec3 corner(c & 1, (c >> 1) & 1, (c >> 2) & 1);
    const Vec3 out = (corner - Vec3::Constant(0.5)).normalized();
    for (int k = 0; k < 20; ++k) {
      const Vec3 jitter(rng.Normal(), rng.Normal(), rng.Normal());
      pts.push_back(corner + 0.3 * out + 0.05 * jitter);   // vertex region
      pts.push_back(corner - 0.05 * out + 0.01 * jitter);  // just inside, near the corner
    }
  }
  for (int a = 0; a < 3; ++a)
    for (int k = 0; k < 40; ++k) {  // beside the edge along axis a through (1, 1, 1)
      Vec3 out = Vec3::Constant(1.0 + 0.1 * rng.Uniform()), in = Vec3::Constant(1.0 - 0.02 * rng.Uniform());
      out[a] = in[a] = rng.Uniform();
      pts.push_back(out);  // edge region, outside
      pts.push_back(in);   // inside, as near the edge as the faces
    }
  const auto [agree, undecided] = Check(cube, pts);
  EXPECT_EQ(undecided, 0);
  EXPECT_EQ(agree, static_cast<int>(pts.size()));
}

// A thin wedge (a tetrahedron flattened to 1/10 of its height): edges and
// corners so sharp that one face's normal gives the wrong side for points
// in their regions; only the edge and vertex pseudonormals get them right.
TEST(PseudonormalSign, SharpEdgesAndCornersNeedTheirOwnPseudonormals) {
  Mesh wedge;
  wedge.V.resize(4, 3);
  wedge.V << 0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, 0.3, 0.1;
  wedge.F.resize(4, 3);
  wedge.F << 0, 2, 1, 0, 1, 3, 1, 2, 3, 2, 0, 3;
  spatial_test::FlipIfInward(&wedge);
  std::vector<Vec3> pts = Random(20000, Vec3(-0.3, -0.3, -0.3), Vec3(1.3, 1.3, 0.4), 13);
  const auto [agree, undecided] = Check(wedge, pts);
  EXPECT_EQ(undecided, 0);
  EXPECT_EQ(agree, static_cast<int>(pts.size()));
  // Some of them do lie where a single face normal is wrong.
  const TriangleBvh bvh(wedge);
  int face_normal_wrong = 0;
  for (const Vec3& q : pts) {
    const TriangleBvh::Hit h = bvh.Closest(q);
    const Vec3 a = wedge.V.row(wedge.F(h.face, 0)), b = wedge.V.row(wedge.F(h.face, 1)),
               c = wedge.V.row(wedge.F(h.face, 2));
    face_normal_wrong += ((q - h.point).dot((b - a).cross(c - a)) < 0) != (WindingNumberExact(wedge, q) > 0.5);
  }
  EXPECT_GT(face_normal_wrong, 10);
}

TEST(PseudonormalSign, SmoothMeshesNearAndFarAgreeWithTheWindingNumber) {
  for (const Mesh& m : {spatial_test::Torus(0.35, 0.15, 60, 30), spatial_test::Icosphere(3, 0.4)}) {
    std::vector<Vec3> pts = Random(3000, Vec3::Constant(-0.8), Vec3::Constant(0.8), 7);
    // Near the surface: vertices pushed a little along random directions.
    Rng rng(9);
    for (int v = 0; v < m.NumVertices(); v += 7)
      pts.push_back(Vec3(m.V.row(v)) + 1e-3 * Vec3(rng.Normal(), rng.Normal(), rng.Normal()));
    const auto [agree, undecided] = Check(m, pts);
    EXPECT_EQ(undecided, 0);
    EXPECT_EQ(agree, static_cast<int>(pts.size()));
  }
}

TEST(PseudonormalSign, OpenMeshesAndNonManifoldCornersAreUndecidedNotWrong) {
  Mesh open = Cube();
  open.F.conservativeResize(10, 3);  // two faces gone: a hole
  const PseudonormalSign s_open(open);
  EXPECT_FALSE(s_open.closed());
  EXPECT_EQ(s_open.Side(Vec3(2, 2, 2), Vec3(1, 1, 1), 0), 0);
  // Two cubes sharing one corner: closed edges, one vertex with two fans.
  const Mesh pair = spatial_test::Concat(Cube(), Cube(Vec3(1, 1, 1)));
  Mesh welded = pair;
  for (int f = 0; f < welded.NumFaces(); ++f)
    for (int k = 0; k < 3; ++k)
      if (welded.F(f, k) == 8) welded.F(f, k) = 7;  // the second cube's corner 0 is the first's corner 7
  const PseudonormalSign s_pair(welded);
  EXPECT_TRUE(s_pair.closed());
  std::vector<Vec3> pts = Random(2000, Vec3::Constant(-0.5), Vec3::Constant(2.5), 11);
  pts.push_back(Vec3(1.2, 0.9, 0.8));  // nearest the shared corner region
  pts.push_back(Vec3(0.8, 1.2, 1.1));
  Check(welded, pts);  // no decided answer may be wrong
  EXPECT_THROW(PseudonormalSign(Mesh{Cube().V, (Eigen::MatrixX3i(1, 3) << 0, 1, 9).finished()}), InputError);
}

}  // namespace
}  // namespace arcs
