// Reach for the Spheres on analytic SDFs: a sphere comes back as a sphere,
// the same seed gives the same mesh at any thread count, a genus-1 input
// never crashes and keeps genus 0, and bad samples fail with clear errors.
#include "framework/geometry/builtin_shapes.h"
#include "framework/rfts/rfts.h"
#include "framework/spatial/topology.h"
#include "framework/spatial/triangle_bvh.h"
#include "framework/util/parallel.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <iostream>

namespace arcs {
namespace {

// SDF of `f` on an n^3 grid over [lo, hi]^3 (scattered form: points + values).
SdfSamples GridSamples(int n, const std::function<double(const Vec3&)>& f, double lo = -1, double hi = 1) {
  SdfSamples s;
  s.dim = 3;
  s.points.resize(static_cast<std::int64_t>(n) * n * n, 3);
  s.values.resize(s.points.rows());
  std::int64_t i = 0;
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x, ++i) {
        const Vec3 p(lo + (hi - lo) * x / (n - 1), lo + (hi - lo) * y / (n - 1), lo + (hi - lo) * z / (n - 1));
        s.points.row(i) = p.transpose();
        s.values[i] = f(p);
      }
  return s;
}

const Vec3 kCentre(0.03, -0.02, 0.01);
constexpr double kRadius = 0.4;
double SphereSdf(const Vec3& p) { return (p - kCentre).norm() - kRadius; }

TEST(Rfts, SphereSdfGivesTheSphere) {
  const SdfSamples s = GridSamples(20, SphereSdf);
  const RftsResult r = ReachForTheSpheres(s, RftsOptions{}, Context(1));
  EXPECT_FALSE(r.singular) << r.stop_reason;
  const Topology t = ComputeTopology(r.mesh);
  EXPECT_TRUE(t.closed && t.manifold && t.oriented);
  EXPECT_EQ(t.genus, 0);
  EXPECT_GT(t.volume, 0);  // outward faces
  double max_err = 0, sum_err = 0;
  for (int v = 0; v < r.mesh.NumVertices(); ++v) {
    const double e = std::abs((r.mesh.V.row(v).transpose() - kCentre).norm() - kRadius);
    max_err = std::max(max_err, e);
    sum_err += e;
  }
  const double mean_err = sum_err / r.mesh.NumVertices();
  std::cout << "sphere: " << r.iterations << " iterations, " << r.halvings << " halvings, " << r.stop_reason
            << ", " << r.mesh.NumVertices() << " vertices, radius error max " << max_err << " mean " << mean_err
            << ", min_h " << r.min_edge_length << "\n";
  // tol = 0.01 is the tangency tolerance of the samples; the vertices sit
  // within it of the true sphere (grid spacing 0.105 for comparison).
  EXPECT_LT(max_err, 0.02) << "iterations " << r.iterations << ", " << r.stop_reason;
  EXPECT_LT(mean_err, 0.005);
  const double volume = 4.0 / 3.0 * M_PI * kRadius * kRadius * kRadius;
  EXPECT_NEAR(t.volume, volume, 0.05 * volume);
}

TEST(Rfts, FrameInvariance) {
  // The same samples scaled by 10 and shifted give the same surface, scaled
  // (up to rounding, which can change a remeshing decision: compared as
  // surfaces, within the tangency tolerance).
  const SdfSamples a = GridSamples(12, SphereSdf);
  SdfSamples b = a;
  const Vec3 shift(5, -3, 2);
  for (std::int64_t i = 0; i < b.Size(); ++i) b.points.row(i) = 10.0 * a.points.row(i) + shift.transpose();
  b.values *= 10.0;
  const RftsResult ra = ReachForTheSpheres(a, RftsOptions{}, Context(3));
  RftsResult rb = ReachForTheSpheres(b, RftsOptions{}, Context(3));
  for (int v = 0; v < rb.mesh.NumVertices(); ++v)
    rb.mesh.V.row(v) = (rb.mesh.V.row(v) - shift.transpose()) / 10.0;
  const TriangleBvh ta(ra.mesh), tb(rb.mesh);
  double worst = 0;
  for (int v = 0; v < rb.mesh.NumVertices(); ++v) worst = std::max(worst, ta.Closest(rb.mesh.V.row(v)).sq_dist);
  for (int v = 0; v < ra.mesh.NumVertices(); ++v) worst = std::max(worst, tb.Closest(ra.mesh.V.row(v)).sq_dist);
  EXPECT_LT(std::sqrt(worst), 0.01) << ra.stop_reason << " / " << rb.stop_reason;
  EXPECT_EQ(ra.stop_reason, rb.stop_reason);
}

TEST(Rfts, SameSeedSameMeshAtOneAndTwoThreads) {
  const SdfSamples s = GridSamples(14, SphereSdf);
  RftsOptions o;
  o.batch_size = 600;  // batches matter: fewer than the 2744 samples
  o.max_iterations = 150;
  Mesh m1, m2, m3;
  {
    ThreadLimit one(1);
    m1 = ReachForTheSpheres(s, o, Context(7)).mesh;
  }
  {
    ThreadLimit two(2);
    m2 = ReachForTheSpheres(s, o, Context(7)).mesh;
  }
  m3 = ReachForTheSpheres(s, o, Context(8)).mesh;
  ASSERT_EQ(m1.V.rows(), m2.V.rows());
  EXPECT_EQ(m1.F, m2.F);
  EXPECT_EQ(m1.V, m2.V);
  EXPECT_FALSE(m1.V.rows() == m3.V.rows() && m1.V == m3.V) << "another seed draws other batches";
}

TEST(Rfts, GenusOneKeepsGenusZeroAndNeverCrashes) {
  // A torus (R = 0.35, r = 0.12): RFTS cannot open the hole. Whether the flow
  // hits a singularity (then: the last converged mesh) or stalls, the output
  // is a closed genus-0 mesh.
  auto torus = [](const Vec3& p) {
    const double q = std::hypot(p.x(), p.y()) - 0.35;
    return std::hypot(q, p.z()) - 0.12;
  };
  RftsOptions o;
  o.max_iterations = 2000;
  const RftsResult r = ReachForTheSpheres(GridSamples(16, torus), o, Context(1));
  const Topology t = ComputeTopology(r.mesh);
  std::cout << "torus: " << r.iterations << " iterations, " << r.stop_reason << ", " << r.mesh.NumVertices()
            << " vertices\n";
  EXPECT_TRUE(t.closed && t.manifold) << r.stop_reason;
  EXPECT_EQ(t.genus, 0) << r.stop_reason;
  EXPECT_NE(r.stop_reason, "converged") << "a genus-0 mesh cannot be tangent to every torus sphere";
}

TEST(Rfts, BadSamplesGiveClearErrors) {
  auto expect_error = [](const SdfSamples& s, const std::string& part) {
    try {
      ReachForTheSpheres(s, RftsOptions{}, Context(1));
      ADD_FAILURE() << "no error, expected one with '" << part << "'";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("rfts"), std::string::npos) << e.what();
    }
  };
  SdfSamples s = GridSamples(6, SphereSdf);
  SdfSamples positive = s;
  positive.values = s.values.cwiseAbs().array() + 0.1;
  expect_error(positive, "no SDF sample is negative");
  SdfSamples negative = s;
  negative.values = -(s.values.cwiseAbs().array() + 0.1);
  expect_error(negative, "no SDF sample is positive");
  SdfSamples nan = s;
  nan.values[17] = std::nan("");
  expect_error(nan, "sample 17");
  SdfSamples inf_point = s;
  inf_point.points(5, 1) = INFINITY;
  expect_error(inf_point, "sample 5");
  SdfSamples one = s;
  one.points.conservativeResize(1, 3);
  one.values.conservativeResize(1);
  expect_error(one, "at least 2");
  SdfSamples mismatched = s;
  mismatched.values.conservativeResize(s.Size() - 3);
  expect_error(mismatched, "values");
  SdfSamples planar = s;
  planar.dim = 2;
  expect_error(planar, "3D");
  RftsOptions bad;
  bad.tol = -1;
  EXPECT_THROW(ReachForTheSpheres(s, bad, Context(1)), OptionError);
}

TEST(Rfts, VoronoiMassSumsToArea) {
  const Mesh m = MakeIcosphere(0.7, 3);
  const Topology t = ComputeTopology(m);
  EXPECT_NEAR(VoronoiMass(m).sum(), t.area, 1e-9 * t.area);
  // An obtuse triangle fan: the mixed areas still sum to the area.
  Mesh tri;
  tri.V.resize(4, 3);
  tri.V << 0, 0, 0, 1, 0, 0, 0.5, 0.05, 0, 0.5, 0, 1;
  tri.F.resize(2, 3);
  tri.F << 0, 1, 2, 0, 1, 3;
  EXPECT_NEAR(VoronoiMass(tri).sum(), ComputeTopology(tri).area, 1e-12);
}

}  // namespace
}  // namespace arcs
