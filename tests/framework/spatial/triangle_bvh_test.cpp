#include "framework/spatial/triangle_bvh.h"

#include "framework/error.h"
#include "framework/util/parallel.h"
#include "framework/util/rng.h"
#include "tests/framework/spatial/spatial_test_meshes.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace arcs {
namespace {

using spatial_test::Icosphere;
using spatial_test::Torus;

// Reference point-triangle squared distance, written independently of the
// library: projection onto the plane when it falls inside, else the closest
// of the three edges.
double SegSq(const Vec3& a, const Vec3& b, const Vec3& q) {
  const Vec3 d = b - a;
  const double dd = d.squaredNorm();
  double t = dd > 0 ? (q - a).dot(d) / dd : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return (a + t * d - q).squaredNorm();
}

double RefTriSq(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& q) {
  const Vec3 e0 = b - a, e1 = c - a, w = q - a;
  const double a00 = e0.dot(e0), a01 = e0.dot(e1), a11 = e1.dot(e1);
  const double det = a00 * a11 - a01 * a01;
  if (det > 1e-14 * a00 * a11) {
    const double b0 = e0.dot(w), b1 = e1.dot(w);
    const double s = (a11 * b0 - a01 * b1) / det, t = (a00 * b1 - a01 * b0) / det;
    if (s >= 0 && t >= 0 && s + t <= 1) return (a + s * e0 + t * e1 - q).squaredNorm();
  }
  return std::min({SegSq(a, b, q), SegSq(b, c, q), SegSq(c, a, q)});
}

double BruteSq(const Mesh& m, const Vec3& q) {
  double best = std::numeric_limits<double>::infinity();
  for (int f = 0; f < m.NumFaces(); ++f)
    best = std::min(best, RefTriSq(m.V.row(m.F(f, 0)), m.V.row(m.F(f, 1)), m.V.row(m.F(f, 2)), q));
  return best;
}

MatrixX3d RandomPoints(int n, double lo, double hi, std::uint64_t seed) {
  Rng rng(seed);
  MatrixX3d Q(n, 3);
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) Q(i, k) = rng.Uniform(lo, hi);
  return Q;
}

// Every answer matches brute force; the returned point lies on the returned
// face at the returned distance. Both builds: the SAH one with oriented boxes
// (the default) and the cheap Morton one (oriented_boxes false).
void CheckAgainstBruteForce(const Mesh& m, const MatrixX3d& Q) {
  for (const bool oriented : {true, false}) {
    SCOPED_TRACE(oriented ? "SAH build, oriented boxes" : "Morton build, axis-aligned boxes");
    const TriangleBvh bvh(m, oriented);
    VectorXd d2;
    MatrixX3d P;
    Eigen::VectorXi F;
    bvh.ClosestPoints(Q, &d2, &P, &F);
    for (int i = 0; i < Q.rows(); ++i) {
      const Vec3 q = Q.row(i);
      const double ref = BruteSq(m, q);
      // Relative 1e-12, or rounding-level when q lies on the surface.
      const double tol = 1e-12 * ref + 1e-28 * (1.0 + q.squaredNorm());
      ASSERT_NEAR(d2[i], ref, tol) << "query " << i;
      ASSERT_GE(F[i], 0);
      const Vec3 p = P.row(i);
      EXPECT_NEAR((p - q).squaredNorm(), d2[i], tol);
      const double on_face = RefTriSq(m.V.row(m.F(F[i], 0)), m.V.row(m.F(F[i], 1)), m.V.row(m.F(F[i], 2)), p);
      EXPECT_LE(on_face, 1e-24 * (1.0 + p.squaredNorm()));
      const TriangleBvh::Hit hit = bvh.Closest(q);
      EXPECT_EQ(hit.sq_dist, d2[i]);
      EXPECT_EQ(hit.face, F[i]);
    }
  }
}

TEST(TriangleBvh, IcosphereMatchesBruteForce) {
  const Mesh m = Icosphere(3);
  CheckAgainstBruteForce(m, RandomPoints(1500, -2.0, 2.0, 1));
  CheckAgainstBruteForce(m, RandomPoints(500, -1.05, 1.05, 2));
}

TEST(TriangleBvh, TorusMatchesBruteForceRandomAndGrid) {
  const Mesh m = Torus(1.0, 0.3, 48, 24);
  CheckAgainstBruteForce(m, RandomPoints(1500, -1.6, 1.6, 3));
  // Grid order exercises the warm-started batch path.
  CheckAgainstBruteForce(m, spatial_test::GridPoints(14, -1.5, 1.5));
}

TEST(TriangleBvh, SphereDistanceIsAnalyticOutside) {
  // Far from a fine icosphere the distance is |q| - 1 up to the chord error.
  const Mesh m = Icosphere(5);
  const TriangleBvh bvh(m);
  const Vec3 q(3.0, -1.0, 2.0);
  const TriangleBvh::Hit hit = bvh.Closest(q);
  EXPECT_NEAR(std::sqrt(hit.sq_dist), q.norm() - 1.0, 2e-3);
  // A vertex of the mesh is at distance 0 and is returned exactly.
  const Vec3 v = m.V.row(17);
  const TriangleBvh::Hit on = bvh.Closest(v);
  EXPECT_EQ(on.sq_dist, 0.0);
  EXPECT_EQ(on.point, v);
}

TEST(TriangleBvh, SearchRadiusLimitsTheAnswer) {
  const Mesh m = Icosphere(2);
  const TriangleBvh bvh(m);
  const Vec3 q(0, 0, 3);  // distance 2 from the unit sphere's vertex (0,0,1)?
  const double d2 = BruteSq(m, q);
  EXPECT_EQ(bvh.Closest(q, 0.99 * d2).face, -1);
  EXPECT_TRUE(std::isinf(bvh.Closest(q, 0.99 * d2).sq_dist));
  const TriangleBvh::Hit hit = bvh.Closest(q, d2);
  EXPECT_GE(hit.face, 0);
  EXPECT_NEAR(hit.sq_dist, d2, 1e-12 * d2);
}

TEST(TriangleBvh, DegenerateFacesGiveFiniteExactAnswers) {
  Mesh m;
  m.V.resize(7, 3);
  m.V << 0, 0, 0,  //
      1, 0, 0,     //
      2, 0, 0,     // collinear with 0 and 1
      0, 1, 0,     //
      0, 1, 0,     // duplicate of 3
      0, 0, 1,     //
      1, 1, 1;
  m.F.resize(5, 3);
  m.F << 0, 1, 2,  // collinear: a segment
      3, 4, 4,     // repeated indices: a point
      3, 4, 5,     // coincident corners: a segment
      0, 0, 0,     // a single point
      1, 6, 5;     // a regular triangle
  const MatrixX3d Q = RandomPoints(800, -1.0, 3.0, 4);
  const TriangleBvh bvh(m);
  VectorXd d2;
  MatrixX3d P;
  bvh.ClosestPoints(Q, &d2, &P);
  ASSERT_TRUE(d2.allFinite());
  ASSERT_TRUE(P.allFinite());
  CheckAgainstBruteForce(m, Q);
  // Only degenerate faces.
  Mesh d;
  d.V = m.V;
  d.F = m.F.topRows(4);
  CheckAgainstBruteForce(d, RandomPoints(300, -1.0, 3.0, 5));
}

TEST(TriangleBvh, SameResultAtOneAndTwoThreads) {
  const Mesh m = Torus(1.0, 0.4, 40, 20);
  const TriangleBvh bvh(m);
  const MatrixX3d Q = spatial_test::GridPoints(24, -1.7, 1.7);
  VectorXd d1, d2;
  Eigen::VectorXi f1, f2;
  {
    ThreadLimit one(1);
    bvh.ClosestPoints(Q, &d1, nullptr, &f1);
  }
  {
    ThreadLimit two(2);
    bvh.ClosestPoints(Q, &d2, nullptr, &f2);
  }
  EXPECT_EQ(d1, d2);
  EXPECT_EQ(f1, f2);
}

// Meshes above 4096 faces build their subtrees in parallel: the tree (and so
// every answer, ties included) is the same whether it was built by one thread
// or two, and exact.
TEST(TriangleBvh, BuiltByOneOrTwoThreadsGivesTheSameAnswers) {
  const Mesh m = Torus(1.0, 0.3, 200, 100);  // 40 000 faces
  const MatrixX3d Q = RandomPoints(400, -1.6, 1.6, 11);
  VectorXd d1, d2;
  MatrixX3d p1, p2;
  Eigen::VectorXi f1, f2;
  {
    ThreadLimit one(1);
    const TriangleBvh bvh(m);
    bvh.ClosestPoints(Q, &d1, &p1, &f1);
  }
  {
    ThreadLimit two(2);
    const TriangleBvh bvh(m);
    bvh.ClosestPoints(Q, &d2, &p2, &f2);
  }
  EXPECT_EQ(d1, d2);
  EXPECT_EQ(p1, p2);
  EXPECT_EQ(f1, f2);
  CheckAgainstBruteForce(m, Q.topRows(150));
  // Axis-aligned boxes only: a different tree, the same answers.
  VectorXd d3;
  MatrixX3d p3;
  Eigen::VectorXi f3;
  TriangleBvh(m, /*oriented_boxes=*/false).ClosestPoints(Q, &d3, &p3, &f3);
  EXPECT_EQ(d1, d3);
  EXPECT_EQ(p1, p3);
  EXPECT_EQ(f1, f3);
  // The Morton split with oriented boxes (fitted from summed moments): again
  // the same answers, at 1 and 2 threads.
  for (int threads : {1, 2}) {
    ThreadLimit limit(threads);
    VectorXd d4;
    MatrixX3d p4;
    Eigen::VectorXi f4;
    TriangleBvh(m, TriangleBvh::BuildKind::kMortonOriented).ClosestPoints(Q, &d4, &p4, &f4);
    EXPECT_EQ(d1, d4);
    EXPECT_EQ(p1, p4);
    EXPECT_EQ(f1, f4);
  }
}

TEST(TriangleBvh, FarFromOriginAndTinyScale) {
  // Float bounds are relative to the mesh's centre: a small mesh far from the
  // origin, or a very small one, must still give exact answers.
  for (const auto& [offset, scale] : {std::pair{Vec3(1e5, -2e5, 3e5), 1.0}, std::pair{Vec3(0.3, 0, 0), 1e-6}}) {
    Mesh m = Torus(1.0, 0.3, 32, 16);
    m.V *= scale;
    m.V.rowwise() += offset.transpose();
    MatrixX3d Q = RandomPoints(400, -1.6 * scale, 1.6 * scale, 8);
    Q.rowwise() += offset.transpose();
    CheckAgainstBruteForce(m, Q);
  }
}

TEST(TriangleBvh, CoincidentTrianglesAndPointsOnTheSurface) {
  // 200 copies of one triangle (all centroids equal: the build must split by
  // count) plus a sphere; queries exactly on vertices and face centroids.
  Mesh s = Icosphere(2);
  Mesh m;
  m.V.resize(s.NumVertices() + 3, 3);
  m.V << s.V, Eigen::RowVector3d(2, 0, 0), Eigen::RowVector3d(2, 1, 0), Eigen::RowVector3d(2, 0, 1);
  m.F.resize(s.NumFaces() + 200, 3);
  m.F.topRows(s.NumFaces()) = s.F;
  for (int i = 0; i < 200; ++i) m.F.row(s.NumFaces() + i) << s.NumVertices(), s.NumVertices() + 1, s.NumVertices() + 2;
  MatrixX3d Q(60, 3);
  for (int i = 0; i < 30; ++i) Q.row(i) = m.V.row(5 * i);
  for (int i = 30; i < 60; ++i) {
    const int f = 7 * i;
    Q.row(i) = (m.V.row(m.F(f, 0)) + m.V.row(m.F(f, 1)) + m.V.row(m.F(f, 2))) / 3.0;
  }
  CheckAgainstBruteForce(m, Q);
  for (const bool oriented : {true, false}) {
    const TriangleBvh bvh(m, oriented);
    // Ties: the copies are equidistant, the lowest face index wins.
    const TriangleBvh::Hit hit = bvh.Closest(Vec3(2.2, 0.2, 0.2));
    EXPECT_EQ(hit.face, s.NumFaces());
    for (int i = 0; i < 30; ++i) EXPECT_EQ(bvh.Closest(Q.row(i)).sq_dist, 0.0);
  }
}

TEST(TriangleBvh, HugeAndNanQueries) {
  const Mesh m = Icosphere(1);
  const TriangleBvh bvh(m);
  const TriangleBvh::Hit far = bvh.Closest(Vec3(1e40, 0, 0));
  EXPECT_GE(far.face, 0);
  EXPECT_NEAR(std::sqrt(far.sq_dist), 1e40, 1e26);
  const TriangleBvh::Hit nan = bvh.Closest(Vec3(NAN, 0, 0));
  EXPECT_EQ(nan.face, -1);
}

TEST(TriangleBvh, TinyMeshesMatchBruteForce) {
  ARCS_REQUIRE_SHARED_DATA();
  for (const char* name : {"spot.obj", "eight.obj"}) {
    SCOPED_TRACE(name);
    Mesh m = spatial_test::ReadObjVF(testing::SharedData(std::string("tiny/") + name));
    spatial_test::NormalizeUnitBox(&m);
    CheckAgainstBruteForce(m, RandomPoints(600, -1.0, 1.0, 9));
    CheckAgainstBruteForce(m, spatial_test::GridPoints(9, -1.0, 1.0));
  }
}

TEST(TriangleBvh, RejectsBadIndicesAndNonFiniteVertices) {
  Mesh m = Icosphere(1);
  m.F(3, 1) = m.NumVertices();
  EXPECT_THROW(TriangleBvh{m}, InputError);
  m = Icosphere(1);
  m.V(m.F(2, 0), 1) = NAN;
  EXPECT_THROW(TriangleBvh{m}, InputError);
}

TEST(TriangleBvh, EmptyMesh) {
  Mesh m;
  m.V.resize(0, 3);
  m.F.resize(0, 3);
  const TriangleBvh bvh(m);
  EXPECT_EQ(bvh.Closest(Vec3(1, 2, 3)).face, -1);
  VectorXd d2;
  MatrixX3d Q = RandomPoints(10, 0, 1, 6);
  bvh.ClosestPoints(Q, &d2);
  EXPECT_TRUE(std::isinf(d2[0]));
}


// Issue 15: a subnormal or near-overflow coordinate made a bin index NaN ->
// INT_MIN (an out-of-bounds stack write in the build). Any finite input must
// build and answer in bounds (ASan/UBSan run this).
TEST(TriangleBvh, ExtremeFiniteCoordinatesStayInBounds) {
  const double vals[] = {1e-310, 4.9e-324, 1e-300, 1e308, -1e308, 1.7976931348623157e308};
  for (double x : vals) {
    Mesh m;
    m.V.resize(6, 3);
    m.V << x, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, x, x, x, -x, 0, -x;
    m.F.resize(5, 3);
    m.F << 0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2, 3, 4, 5;
    for (const bool oriented : {true, false}) {
      const TriangleBvh bvh(m, oriented);
      const auto hit = bvh.Closest(Vec3(0.25, 0.25, 0.25));
      // Near DBL_MAX squared distances overflow: "nothing found" is allowed there.
      if (std::abs(x) < 1e150) {
        EXPECT_GE(hit.face, 0) << x;
      }
      EXPECT_GE(hit.face, -1) << x;
      EXPECT_LT(hit.face, m.NumFaces()) << x;
      // Many triangles sharing a subnormal-wide centroid spread.
      Mesh many;
      many.V.resize(3 * 64, 3);
      many.F.resize(64, 3);
      for (int f = 0; f < 64; ++f) {
        for (int k = 0; k < 3; ++k) many.V.row(3 * f + k) = Vec3(f * (x * 1e-3), k == 1 ? 1.0 : 0.0, k == 2 ? 1.0 : 0.0);
        many.F.row(f) << 3 * f, 3 * f + 1, 3 * f + 2;
      }
      const TriangleBvh b2(many, oriented);
      if (std::abs(x) < 1e150) {
        EXPECT_GE(b2.Closest(Vec3(0, 0.5, 0.5)).face, 0) << x;
      }
    }
  }
}

}  // namespace
}  // namespace arcs
