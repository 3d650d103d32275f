// Screened Poisson reconstruction on exact samples of analytic shapes.
#include "framework/reconstruct/poisson.h"

#include "framework/error.h"
#include "framework/geometry/builtin_shapes.h"
#include "framework/geometry/surface_sampling.h"
#include "framework/spatial/topology.h"
#include "framework/util/rng.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <string>

namespace arcs {
namespace {

constexpr double kPi = std::numbers::pi;

#define REQUIRE_PCL()                                                                  \
  do {                                                                                 \
    if (!PoissonAvailable()) GTEST_SKIP() << "arcs was built without PCL (libpcl-dev)"; \
  } while (0)

// n points exactly on the sphere |p - c| = r with exact outward normals.
PointCloud SpherePoints(int n, double r = 0.5, const Vec3& c = Vec3::Zero(), std::uint64_t seed = 7) {
  PointCloud pc;
  pc.P.resize(n, 3);
  pc.N.resize(n, 3);
  Rng rng(seed);
  for (int i = 0; i < n; ++i) {
    const Vec3 d = Vec3(rng.Normal(), rng.Normal(), rng.Normal()).normalized();
    pc.N.row(i) = d;
    pc.P.row(i) = c + r * d;
  }
  return pc;
}

// Area-uniform points on the built-in torus (R = 0.35, r = 0.15) with the
// normals of the faces they lie on.
PointCloud TorusPoints(int n) {
  const Mesh t = MakeTorus();
  PointCloud pc;
  Eigen::VectorXi face;
  pc.P = SampleSurfaceUniform(t, n, 11, &face);
  pc.N.resize(n, 3);
  for (int i = 0; i < n; ++i) {
    const Vec3 a = t.V.row(t.F(face[i], 0)), b = t.V.row(t.F(face[i], 1)), c = t.V.row(t.F(face[i], 2));
    pc.N.row(i) = (b - a).cross(c - a).normalized();
  }
  return pc;
}

double MaxDeviation(const Mesh& m, const std::function<double(const Vec3&)>& dist) {
  double worst = 0.0;
  for (int i = 0; i < m.NumVertices(); ++i) worst = std::max(worst, dist(m.V.row(i).transpose()));
  return worst;
}

PoissonOptions Depth(int d) {
  PoissonOptions o;
  o.depth = d;
  return o;
}

// Expects `fn` to throw arcs::Error whose message contains `part`.
void ExpectError(const std::function<void()>& fn, const std::string& part) {
  try {
    fn();
    ADD_FAILURE() << "no error thrown; expected one mentioning '" << part << "'";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
}

TEST(Poisson, SphereIsClosedGenusZeroAndOnTheSphere) {
  REQUIRE_PCL();
  const PointCloud pc = SpherePoints(5000);
  const Mesh m = ReconstructPoisson(pc, Depth(7), Context());
  const Topology t = ComputeTopology(m);
  EXPECT_TRUE(t.closed);
  EXPECT_TRUE(t.manifold);
  EXPECT_TRUE(t.oriented);
  EXPECT_EQ(t.components, 1);
  EXPECT_EQ(t.genus, 0);
  EXPECT_EQ(t.degenerate_faces, 0);
  EXPECT_EQ(t.referenced_vertices, t.vertices);
  EXPECT_GT(m.NumVertices(), 5000);  // finer than the samples: ~14.5k measured
  // Outward: positive volume, close to the ball's (inscribed polyhedron).
  EXPECT_NEAR(t.volume, 4.0 / 3.0 * kPi * 0.125, 0.005);
  EXPECT_NEAR(t.area, kPi, 0.01);
  // Measured: mean 1.7e-4, max 1.3e-3 at 5k points (radius 0.5).
  EXPECT_LT(MaxDeviation(m, [](const Vec3& p) { return std::abs(p.norm() - 0.5); }), 3e-3);
}

TEST(Poisson, TorusIsGenusOne) {
  REQUIRE_PCL();
  const PointCloud pc = TorusPoints(5000);
  const Mesh m = ReconstructPoisson(pc, Depth(7), Context());
  const Topology t = ComputeTopology(m);
  EXPECT_TRUE(t.closed);
  EXPECT_TRUE(t.manifold);
  EXPECT_EQ(t.components, 1);
  EXPECT_EQ(t.genus, 1);
  EXPECT_NEAR(t.volume, 2 * kPi * kPi * 0.35 * 0.15 * 0.15, 0.003);
  const double dev = MaxDeviation(m, [](const Vec3& p) {
    return std::abs(std::hypot(std::hypot(p.x(), p.y()) - 0.35, p.z()) - 0.15);
  });
  EXPECT_LT(dev, 3e-3);  // measured 1.3e-3
}

TEST(Poisson, MeshIsInTheInputCoordinates) {
  REQUIRE_PCL();
  // Far from the origin and large: arcs normalises before PCL's single
  // precision and maps back.
  const Vec3 c(1000.0, -2000.0, 500.0);
  const PointCloud pc = SpherePoints(3000, 50.0, c);
  const Mesh m = ReconstructPoisson(pc, Depth(6), Context());
  const Topology t = ComputeTopology(m);
  EXPECT_EQ(t.genus, 0);
  EXPECT_LT(MaxDeviation(m, [&](const Vec3& p) { return std::abs((p - c).norm() - 50.0); }), 0.3);
}

TEST(Poisson, InwardNormalsGiveTheSameOutwardSurface) {
  REQUIRE_PCL();
  PointCloud pc = SpherePoints(2000);
  const Mesh out = ReconstructPoisson(pc, Depth(6), Context());
  pc.N = -pc.N;
  const Mesh in = ReconstructPoisson(pc, Depth(6), Context());
  const Topology t = ComputeTopology(in);
  EXPECT_TRUE(t.closed);
  EXPECT_GT(t.volume, 0.5);  // flipped to outward (ball volume 0.524)
  ASSERT_EQ(in.NumVertices(), out.NumVertices());
  EXPECT_LT((in.V - out.V).cwiseAbs().maxCoeff(), 1e-6);
}

TEST(Poisson, DeterministicAndCanonicallyOrdered) {
  REQUIRE_PCL();
  const PointCloud pc = TorusPoints(3000);
  const Mesh a = ReconstructPoisson(pc, Depth(6), Context());
  const Mesh b = ReconstructPoisson(pc, Depth(6), Context());
  ASSERT_EQ(a.NumVertices(), b.NumVertices());
  ASSERT_EQ(a.NumFaces(), b.NumFaces());
  EXPECT_TRUE(a.V == b.V);
  EXPECT_TRUE(a.F == b.F);
  // Canonical order: vertices strictly increasing lexicographically (no two
  // at one position), each face starting at its smallest index.
  for (int i = 1; i < a.NumVertices(); ++i) {
    const auto p = a.V.row(i - 1), q = a.V.row(i);
    ASSERT_TRUE(std::lexicographical_compare(p.begin(), p.end(), q.begin(), q.end())) << i;
  }
  for (int f = 0; f < a.NumFaces(); ++f) ASSERT_LT(a.F(f, 0), std::min(a.F(f, 1), a.F(f, 2)));
}

TEST(Poisson, AutomaticDepthFollowsTheSpacingNotThePlacement) {
  PoissonOptions o;  // depth 0: automatic
  // Calibrated on exact sphere samples (see poisson.h): 5k -> 7, 20k -> 8.
  const PointCloud small = SpherePoints(5000);
  EXPECT_EQ(AutoPoissonDepth(small, o), 7);
  EXPECT_EQ(AutoPoissonDepth(SpherePoints(20000), o), 8);
  // Invariant under scaling and translation.
  PointCloud moved = small;
  moved.P = (small.P * 1e-3).rowwise() + Vec3(5, 6, 7).transpose();
  EXPECT_EQ(AutoPoissonDepth(moved, o), 7);
  // Clamped: 12 points -> the minimum.
  EXPECT_EQ(AutoPoissonDepth(SpherePoints(12), o), PoissonOptions::kMinAutoDepth);
}

TEST(Poisson, BadInputsAreErrorsNotCrashes) {
  const PoissonOptions o = Depth(6);
  const Context ctx;
  auto run = [&](const PointCloud& pc) { return [&, pc] { ReconstructPoisson(pc, o, ctx); }; };
  ExpectError(run(SpherePoints(9)), "at least 10");
  ExpectError(run(PointCloud{}), "at least 10");
  PointCloud no_normals = SpherePoints(100);
  no_normals.N.resize(0, 3);
  ExpectError(run(no_normals), "one normal per point");
  PointCloud nan_point = SpherePoints(100);
  nan_point.P(17, 1) = std::numeric_limits<double>::quiet_NaN();
  ExpectError(run(nan_point), "row 17");
  PointCloud inf_normal = SpherePoints(100);
  inf_normal.N(3, 2) = std::numeric_limits<double>::infinity();
  ExpectError(run(inf_normal), "non-finite component (first: row 3)");
  PointCloud zero_normal = SpherePoints(100);
  zero_normal.N.row(42).setZero();
  ExpectError(run(zero_normal), "zero-length normal(s) (first: row 42)");
  PointCloud coincident = SpherePoints(100);
  coincident.P.rowwise() = Vec3(1, 2, 3).transpose();
  ExpectError(run(coincident), "all points coincide");
}

TEST(Poisson, OptionsAreChecked) {
  auto bad = [](const std::function<void(PoissonOptions&)>& set, const std::string& field) {
    PoissonOptions o;
    set(o);
    try {
      o.Check();
      ADD_FAILURE() << field << ": no OptionError";
    } catch (const OptionError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(field + " = ", 0), 0u) << e.what();
    }
  };
  PoissonOptions().Check();  // defaults are valid
  bad([](PoissonOptions& o) { o.depth = 1; }, "depth");
  bad([](PoissonOptions& o) { o.depth = 13; }, "depth");
  bad([](PoissonOptions& o) { o.min_depth = -1; }, "min_depth");
  bad([](PoissonOptions& o) { o.point_weight = -1; }, "point_weight");
  bad([](PoissonOptions& o) { o.samples_per_node = 0.1; }, "samples_per_node");
  bad([](PoissonOptions& o) { o.scale = 1.0; }, "scale");
  bad([](PoissonOptions& o) { o.threads = 0; }, "threads");
}

TEST(Poisson, WithoutPclTheErrorSaysWhatToInstall) {
  if (PoissonAvailable()) GTEST_SKIP() << "built with PCL";
  ExpectError([] { ReconstructPoisson(SpherePoints(100), PoissonOptions(), Context()); },
              "install libpcl-dev");
}

}  // namespace
}  // namespace arcs
