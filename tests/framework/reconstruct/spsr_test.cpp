// arcs' own screened Poisson (spsr.h) on exact samples of analytic shapes:
// closed, manifold, outward, the right topology and size; deterministic;
// warm start converges to the same surface in fewer steps; bad input refused.
#include "framework/reconstruct/spsr.h"
#include "framework/util/parallel.h"

#include "framework/error.h"
#include "framework/geometry/builtin_shapes.h"
#include "framework/points/sample_points.h"
#include "framework/reconstruct/poisson.h"
#include "framework/spatial/topology.h"
#include "framework/util/rng.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

namespace arcs {
namespace {

constexpr double kPi = std::numbers::pi;

PointCloud SpherePoints(int n, double r, const Vec3& c, std::uint64_t seed) {
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

PointCloud TorusPoints(int n, std::uint64_t seed) {
  SurfacePointOptions o;
  o.count = n;
  return SampleSurfacePoints(MakeTorus(), o, seed);
}

double Volume(const Mesh& m) {
  double v = 0;
  for (int f = 0; f < m.NumFaces(); ++f) {
    const Vec3 a = m.V.row(m.F(f, 0)), b = m.V.row(m.F(f, 1)), c = m.V.row(m.F(f, 2));
    v += a.dot(b.cross(c)) / 6.0;
  }
  return v;
}

// One closed genus-0 component, every vertex within 3 % of radius r of the origin.
void ExpectClosedSphereAtOrigin(const Mesh& m, double r) {
  const Topology t = ComputeTopology(m);
  EXPECT_EQ(t.components, 1);
  EXPECT_EQ(t.boundary_edges, 0);
  EXPECT_EQ(t.genus, 0);
  double worst = 0;
  for (int i = 0; i < m.NumVertices(); ++i) worst = std::max(worst, std::abs(Vec3(m.V.row(i)).norm() - r));
  EXPECT_LT(worst, 0.03 * r);
}

TEST(Spsr, SphereIsClosedRoundAndOutward) {
  const double r = 0.5;
  const Vec3 c(0.2, -0.1, 3.0);  // off the origin: the frame must map back
  const PointCloud pc = SpherePoints(3000, r, c, 7);
  SpsrInfo info;
  const Mesh m = ReconstructSpsr(pc, SpsrOptions{}, Context(1), nullptr, &info);
  const Topology t = ComputeTopology(m);
  EXPECT_EQ(t.components, 1);
  EXPECT_EQ(t.boundary_edges, 0);
  EXPECT_EQ(t.nonmanifold_edges, 0);
  EXPECT_EQ(t.genus, 0);
  double mean = 0, worst = 0;
  for (int i = 0; i < m.NumVertices(); ++i) {
    const double d = (Vec3(m.V.row(i)) - c).norm();
    mean += d;
    worst = std::max(worst, std::abs(d - r));
  }
  mean /= m.NumVertices();
  EXPECT_NEAR(mean, r, 0.005 * r);
  EXPECT_LT(worst, 0.03 * r);
  // Outward winding: positive volume close to the ball's.
  EXPECT_NEAR(Volume(m), 4.0 / 3.0 * kPi * r * r * r, 0.03 * 4.0 / 3.0 * kPi * r * r * r);
  // The estimated area (cube units) is the sphere's within the estimate's bias.
  const double side = 3.2 * 2 * r;
  const double true_area = 4 * kPi * r * r / (side * side);
  EXPECT_GT(info.area, 0.8 * true_area);
  EXPECT_LT(info.area, 1.6 * true_area);
}

TEST(Spsr, ExtractMaxCellCoarsensOnlyTheMarchingCubes) {
  // A sphere of radius 0.5 (cube side 3.2 x 1 = 3.2): the median sample
  // depth's level is finer than cells of side 0.1, so a 0.1 cap extracts at
  // ceil(log2(3.2 / 0.1)) = 5, the complete level; a cap below the finest
  // cell changes nothing. Both closed spheres of the right size.
  const PointCloud pc = SpherePoints(3000, 0.5, Vec3::Zero(), 7);
  SpsrInfo fine, coarse, same;
  const Mesh a = ReconstructSpsr(pc, SpsrOptions{}, Context(1), nullptr, &fine);
  SpsrOptions o;
  o.extract_max_cell = 0.1;
  const Mesh b = ReconstructSpsr(pc, o, Context(1), nullptr, &coarse);
  o.extract_max_cell = 1e-6;
  const Mesh c = ReconstructSpsr(pc, o, Context(1), nullptr, &same);
  EXPECT_GT(fine.extract_depth, 5);
  EXPECT_EQ(coarse.extract_depth, 5);
  EXPECT_EQ(same.extract_depth, fine.extract_depth);
  EXPECT_EQ(c.V, a.V);
  EXPECT_EQ(c.F, a.F);
  EXPECT_LT(b.NumVertices(), a.NumVertices() / 4);
  const Topology t = ComputeTopology(b);
  EXPECT_EQ(t.components, 1);
  EXPECT_EQ(t.boundary_edges, 0);
  EXPECT_NEAR(Volume(b), Volume(a), 0.05 * Volume(a));
  o.extract_max_cell = -1;
  EXPECT_THROW(ReconstructSpsr(pc, o, Context(1)), OptionError);
}

TEST(Spsr, DensityScaleScalesTheAreaAndCeilSplatKeepsTheSurface) {
  // The tent density reads 1/2 to 1 (2/3 on average) of an evenly sampled
  // sheet's samples per node area; on 3000 random points of a sphere the
  // clumps raise it, and the default's estimated area comes out about 1.3x
  // the sphere's (measured 1.296). density_scale 1.5 divides every sample's
  // area by 1.5 (0.85x here). normal_splat ceil moves every normal to its
  // sample's finer level: a different solution, still a closed round
  // sphere, at the same extraction level.
  const double r = 0.5;
  const PointCloud pc = SpherePoints(3000, r, Vec3::Zero(), 7);
  const double side = 3.2 * 2 * r;
  const double true_area = 4 * kPi * r * r / (side * side);
  SpsrInfo base, scaled, ceil;
  const Mesh a = ReconstructSpsr(pc, SpsrOptions{}, Context(1), nullptr, &base);
  SpsrOptions o;
  o.density_scale = 1.5;
  ReconstructSpsr(pc, o, Context(1), nullptr, &scaled);
  EXPECT_GT(base.area / true_area, 1.15) << base.area / true_area;
  EXPECT_LT(base.area / true_area, 1.45) << base.area / true_area;
  EXPECT_NEAR(scaled.area / base.area, 1.0 / 1.5, 0.03) << scaled.area / base.area;
  SpsrOptions c;
  c.normal_splat = SpsrOptions::NormalSplat::kCeil;
  const Mesh b = ReconstructSpsr(pc, c, Context(1), nullptr, &ceil);
  EXPECT_EQ(ceil.extract_depth, base.extract_depth);
  EXPECT_DOUBLE_EQ(ceil.area, base.area);  // the density is not touched
  EXPECT_NE(b.V, a.V);
  ExpectClosedSphereAtOrigin(b, r);
  // iso_weight count: the samples alike (their areas vary), another
  // iso-value on the same solution, the same closed round sphere.
  SpsrOptions w;
  w.iso_weight = SpsrOptions::IsoWeight::kCount;
  SpsrInfo counted;
  const Mesh e = ReconstructSpsr(pc, w, Context(1), nullptr, &counted);
  EXPECT_NE(counted.iso_value, base.iso_value);
  EXPECT_EQ(ComputeTopology(e).genus, 0);
  EXPECT_NEAR(Volume(e), Volume(a), 0.03 * Volume(a));
  o.density_scale = 0.0;
  EXPECT_THROW(ReconstructSpsr(pc, o, Context(1)), OptionError);
}

TEST(Spsr, MergedScreeningKeepsTheSurfaceAndDiffersFromEach) {
  // screen_samples merged: the samples of one cell screen its level as one
  // point at their mean, weighted by their count. On the coarse levels (many
  // samples per cell) that is a weaker term than each sample's own, so the
  // solution differs; it is still a closed round sphere, the same at one and
  // two threads, with the density and extraction level untouched.
  const double r = 0.5;
  const PointCloud pc = SpherePoints(3000, r, Vec3::Zero(), 7);
  SpsrInfo each, merged;
  const Mesh a = ReconstructSpsr(pc, SpsrOptions{}, Context(1), nullptr, &each);
  SpsrOptions o;
  o.screen_samples = SpsrOptions::ScreenSamples::kMerged;
  Mesh b;
  {
    ThreadLimit limit(1);
    b = ReconstructSpsr(pc, o, Context(1), nullptr, &merged);
  }
  EXPECT_EQ(merged.extract_depth, each.extract_depth);
  EXPECT_DOUBLE_EQ(merged.area, each.area);
  EXPECT_NE(merged.iso_value, each.iso_value);
  ExpectClosedSphereAtOrigin(b, r);
  EXPECT_NEAR(Volume(b), Volume(a), 0.03 * Volume(a));
  {
    ThreadLimit limit(2);
    const Mesh c = ReconstructSpsr(pc, o, Context(1));
    EXPECT_EQ(c.V, b.V);
    EXPECT_EQ(c.F, b.F);
  }
}

TEST(Spsr, TorusHasGenusOne) {
  const Mesh m = ReconstructSpsr(TorusPoints(4000, 3), SpsrOptions{}, Context(1));
  const Topology t = ComputeTopology(m);
  EXPECT_EQ(t.components, 1);
  EXPECT_EQ(t.boundary_edges, 0);
  EXPECT_EQ(t.genus, 1);
}

TEST(Spsr, ScreeningTightensSparseExactSamples) {
  // On 600 exact torus samples (R 0.35, r 0.15) the screened solution hugs the
  // surface more closely than the unscreened one, which smooths the thin
  // tube (bench/spsr_bench: Chamfer 0.0024 at weight 10 against 0.0033 at 2).
  const PointCloud pc = TorusPoints(600, 9);
  auto err = [&](double w) {
    SpsrOptions o;
    o.point_weight = w;
    const Mesh m = ReconstructSpsr(pc, o, Context(1));
    double e = 0;
    for (int i = 0; i < m.NumVertices(); ++i) {
      const Vec3 v = m.V.row(i);
      e += std::abs(std::hypot(std::hypot(v.x(), v.y()) - 0.35, v.z()) - 0.15);
    }
    return e / m.NumVertices();
  };
  const double screened = err(10.0), unscreened = err(0.0);
  EXPECT_LT(screened, 0.8 * unscreened) << screened << " vs " << unscreened;
}

TEST(Spsr, DeterministicAndWarmStartConverges) {
  const PointCloud pc = TorusPoints(3000, 5);
  const SpsrOptions o;
  const Mesh a = ReconstructSpsr(pc, o, Context(1));
  const Mesh b = ReconstructSpsr(pc, o, Context(1));
  ASSERT_EQ(a.V.rows(), b.V.rows());
  ASSERT_EQ(a.F.rows(), b.F.rows());
  EXPECT_EQ(a.V, b.V);
  EXPECT_EQ(a.F, b.F);
  // Warm start from the solution of slightly moved points (a fine-tuning step).
  std::shared_ptr<SpsrWarmStart> warm;
  SpsrInfo cold_info, warm_info;
  ReconstructSpsr(pc, o, Context(1), &warm, &cold_info);
  ASSERT_TRUE(warm);
  PointCloud moved = pc;
  Rng rng(2);
  for (int i = 0; i < moved.Size(); ++i)
    moved.P.row(i) += 0.001 * Eigen::RowVector3d(rng.Normal(), rng.Normal(), rng.Normal());
  SpsrInfo moved_cold;
  const Mesh mc = ReconstructSpsr(moved, o, Context(1), nullptr, &moved_cold);
  const Mesh mw = ReconstructSpsr(moved, o, Context(1), &warm, &warm_info);
  EXPECT_TRUE(warm_info.warm_started);
  EXPECT_LT(warm_info.cg_iterations, moved_cold.cg_iterations);
  // Same surface to well below a cell (cube 3.2 x 0.99 / 2^8 ~ 0.012).
  EXPECT_NEAR(Volume(mw), Volume(mc), 0.01 * Volume(mc));
  EXPECT_EQ(ComputeTopology(mw).genus, 1);
}

// Every parallel part (constraints, neighbour tables, the CG, the extraction's
// value rounds) sums each entry on its own: one thread and two give the same mesh.
TEST(Spsr, SameMeshAtOneAndTwoThreads) {
  const PointCloud pc = TorusPoints(20000, 7);
  const SpsrOptions o;
  Mesh one, two;
  {
    ThreadLimit limit(1);
    one = ReconstructSpsr(pc, o, Context(1));
  }
  {
    ThreadLimit limit(2);
    two = ReconstructSpsr(pc, o, Context(1));
  }
  ASSERT_GT(one.NumFaces(), 1000);
  EXPECT_EQ(one.V, two.V);
  EXPECT_EQ(one.F, two.F);
}

// Mean distance of a mesh's vertices from TorusPoints' torus (radii 0.35, 0.15).
double TubeError(const Mesh& m) {
  double e = 0;
  for (int i = 0; i < m.NumVertices(); ++i) {
    const Vec3 v = m.V.row(i);
    e += std::abs(std::hypot(std::hypot(v.x(), v.y()) - 0.35, v.z()) - 0.15);
  }
  return e / m.NumVertices();
}

// The solvers of the levels above the complete one (SpsrOptions::FineSolver):
// each gives the torus with its genus, hugging the true surface as closely as
// the default; the Gauss-Seidel-preconditioned CG stops at the same residual
// in fewer steps; every mode gives the same bits at one and two threads (the
// colours update in parallel, each node writing only its own samples).
TEST(Spsr, FineSolversAgreeAndAreThreadCountIndependent) {
  const PointCloud pc = TorusPoints(20000, 7);
  SpsrOptions jac;
  SpsrInfo jac_info;
  const Mesh base = ReconstructSpsr(pc, jac, Context(1), nullptr, &jac_info);
  const double base_err = TubeError(base);
  for (auto mode : {SpsrOptions::FineSolver::kCgGaussSeidel, SpsrOptions::FineSolver::kGaussSeidel}) {
    SCOPED_TRACE(static_cast<int>(mode));
    SpsrOptions o;
    o.fine_solver = mode;
    Mesh one, two;
    SpsrInfo info;
    {
      ThreadLimit limit(1);
      one = ReconstructSpsr(pc, o, Context(1), nullptr, &info);
    }
    {
      ThreadLimit limit(2);
      two = ReconstructSpsr(pc, o, Context(1));
    }
    ASSERT_GT(one.NumFaces(), 1000);
    EXPECT_EQ(one.V, two.V);
    EXPECT_EQ(one.F, two.F);
    const Topology t = ComputeTopology(one);
    EXPECT_EQ(t.components, 1);
    EXPECT_EQ(t.boundary_edges, 0);
    EXPECT_EQ(t.genus, 1);
    // Exact samples: the surface within a few % of a cell of the tube
    // (cell ~ 3.2 x 1 / 2^10 ~ 0.003) and no farther than the default's + 10 %.
    const double err = TubeError(one);
    EXPECT_LT(err, 1.1 * base_err + 1e-4) << err << " vs cg_jacobi " << base_err;
    EXPECT_NEAR(Volume(one), Volume(base), 0.01 * Volume(base));
    if (mode == SpsrOptions::FineSolver::kCgGaussSeidel) {
      EXPECT_LT(info.cg_iterations, jac_info.cg_iterations);
      EXPECT_LE(info.final_residual, std::max(jac_info.final_residual, 1e-3) * 1.0001);
    } else {
      EXPECT_GT(info.final_residual, 0.0);  // measured after the sweeps
      EXPECT_LT(info.final_residual, 0.5);
    }
  }
}

// The complete level's tolerance (SpsrOptions::base_accuracy): a looser one
// takes fewer multigrid-preconditioned CG steps there and gives the same torus
// (sparse exact samples, where the complete level carries most of the
// solution), as close to the true tube as the tight default.
TEST(Spsr, LooserBaseAccuracyTakesFewerStepsForTheSameSurface) {
  const PointCloud pc = TorusPoints(800, 11);
  SpsrOptions tight;  // 1e-6
  SpsrOptions loose;
  loose.base_accuracy = 1e-3;
  SpsrInfo ti, li;
  const Mesh a = ReconstructSpsr(pc, tight, Context(1), nullptr, &ti);
  const Mesh b = ReconstructSpsr(pc, loose, Context(1), nullptr, &li);
  EXPECT_LT(li.cg_iterations, ti.cg_iterations);
  const Topology t = ComputeTopology(b);
  EXPECT_EQ(t.components, 1);
  EXPECT_EQ(t.boundary_edges, 0);
  EXPECT_EQ(t.genus, 1);
  EXPECT_NEAR(Volume(b), Volume(a), 0.01 * Volume(a));
  EXPECT_LT(TubeError(b), 1.1 * TubeError(a) + 1e-4);
  SpsrOptions bad;
  bad.base_accuracy = 0;
  EXPECT_THROW(ReconstructSpsr(pc, bad, Context(1)), OptionError);
}

TEST(Spsr, StrayPointsInsideMakeNoVoids) {
  // Tangency points that fine-tuning leaves a little inside a solid: each is
  // pinned to the iso-value by the screening and made a one-node void (an
  // 8-triangle component) before remove_node_islands.
  PointCloud pc = SpherePoints(20000, 0.5, Vec3::Zero(), 8);
  const int base = pc.Size(), extra = 40;
  pc.P.conservativeResize(base + extra, 3);
  pc.N.conservativeResize(base + extra, 3);
  Rng rng(4);
  for (int i = 0; i < extra; ++i) {
    const Vec3 d = Vec3(rng.Normal(), rng.Normal(), rng.Normal()).normalized();
    pc.P.row(base + i) = 0.475 * d;
    pc.N.row(base + i) = d;
  }
  SpsrOptions o;
  SpsrInfo info;
  const Mesh clean = ReconstructSpsr(pc, o, Context(1), nullptr, &info);
  o.remove_node_islands = false;
  const Mesh raw = ReconstructSpsr(pc, o, Context(1));
  const int raw_components = ComputeTopology(raw).components;
  EXPECT_EQ(ComputeTopology(clean).components, 1) << "without the removal: " << raw_components;
  EXPECT_GT(raw_components, 1) << "the stray points no longer make voids: this test shows nothing";
  EXPECT_GT(info.islands_removed, 0);
}

TEST(Spsr, CarvingRemovesABallAndFollowsItsBoundary) {
  // A sphere of radius 0.5 with a ball of radius 0.25 carved out at (0.5, 0,
  // 0), on its surface: the solid left is the sphere minus the ball. The
  // mesh stays closed and manifold, no vertex lies inside the ball by more
  // than a marching-cubes cell, the dent's vertices lie on the ball's
  // sphere, and the volume is the sphere's minus the lens. A field that
  // carves nothing gives the uncarved mesh to the bit. (The dent's vertices
  // are the zeros of the field interpolated linearly along cell edges: on
  // the sphere within the chord error cell^2 / (8 rb), inside it, as the
  // field is concave along a line.)
  const PointCloud pc = SpherePoints(6000, 0.5, Vec3::Zero(), 7);
  const Vec3 b(0.5, 0, 0);
  const double rb = 0.25;
  SpsrOptions o;
  SpsrInfo plain_info, info;
  const Mesh plain = ReconstructSpsr(pc, o, Context(1), nullptr, &plain_info);
  o.carve.value = [&](const Vec3& x) { return rb - (x - b).norm(); };
  o.carve.near = [&](const std::vector<Vec3>& x, double, std::vector<double>& c) {
    c.resize(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) c[i] = o.carve.value(x[i]);
  };
  const Mesh m = ReconstructSpsr(pc, o, Context(1), nullptr, &info);
  {
    // A field that gives only a bound beyond reach (as SpsrCarve::near
    // allows): the same mesh, with value() asked only where needed.
    SpsrOptions o2 = o;
    int asked = 0;
    o2.carve.near = [&](const std::vector<Vec3>& x, double reach, std::vector<double>& c) {
      EXPECT_GT(reach, 0);
      c.resize(x.size());
      for (std::size_t i = 0; i < x.size(); ++i) {
        const double v = rb - (x[i] - b).norm();
        c[i] = std::abs(v) < reach ? v : (v > 0 ? reach + 1.0 : -reach - 1.0);
      }
    };
    o2.carve.value = [&](const Vec3& x) {
      ++asked;
      return rb - (x - b).norm();
    };
    const Mesh m2 = ReconstructSpsr(pc, o2, Context(1));
    EXPECT_EQ(m2.V, m.V);
    EXPECT_EQ(m2.F, m.F);
    EXPECT_EQ(asked, 0);  // c is 1-Lipschitz: a claimed node's neighbours are within reach
  }
  const Topology t = ComputeTopology(m);
  EXPECT_EQ(t.components, 1);
  EXPECT_EQ(t.boundary_edges, 0);
  EXPECT_EQ(t.nonmanifold_edges, 0);
  EXPECT_EQ(t.genus, 0);
  EXPECT_GT(info.carved_nodes, 0);
  EXPECT_EQ(plain_info.carved_nodes, 0);
  const double cell = 3.2 / (1 << info.extract_depth);
  const double chord = cell * cell / (8 * rb);
  int on_ball = 0;
  for (int i = 0; i < m.NumVertices(); ++i) {
    const Vec3 v = m.V.row(i);
    const double db = (v - b).norm() - rb;  // < 0: inside the ball
    EXPECT_GT(db, -chord - 1e-12) << "vertex " << i << " inside the carved ball";
    if (v.norm() < 0.5 - 0.02) {  // off the sphere: on the dent
      EXPECT_LT(std::abs(db), chord + 1e-12) << "vertex " << i;
      ++on_ball;
    }
  }
  EXPECT_GT(on_ball, 20);
  // The lens: two caps of the balls R = 0.5 and r = 0.25, centres 0.5 apart.
  const double R = 0.5, r = rb, dd = 0.5;
  const double lens = kPi * (R + r - dd) * (R + r - dd) *
                      (dd * dd + 2 * dd * r - 3 * r * r + 2 * dd * R + 6 * r * R - 3 * R * R) / (12 * dd);
  EXPECT_NEAR(Volume(m), Volume(plain) - lens, 0.1 * lens + 2 * cell * cell);
  // A field negative everywhere carves nothing: the same mesh.
  o.carve.near = [](const std::vector<Vec3>& x, double, std::vector<double>& c) { c.assign(x.size(), -1.0); };
  o.carve.value = [](const Vec3&) { return -1.0; };
  const Mesh same = ReconstructSpsr(pc, o, Context(1));
  ASSERT_EQ(same.V.rows(), plain.V.rows());
  EXPECT_EQ(same.V, plain.V);
  EXPECT_EQ(same.F, plain.F);
}

// A ball lying wholly inside χ's solid: carving it would leave a closed void
// around it, a component with no vertex on χ's surface. By default it is
// dropped and the mesh is the uncarved one to the bit; carve_keep_voids keeps
// it (a second closed component, facing inward: the volume falls by the
// ball's).
TEST(Spsr, CarvingDropsAVoidItAloneWouldMake) {
  const PointCloud pc = SpherePoints(6000, 0.5, Vec3::Zero(), 7);
  const double rb = 0.12;
  SpsrOptions o;
  const Mesh plain = ReconstructSpsr(pc, o, Context(1));
  o.carve.value = [&](const Vec3& x) { return rb - x.norm(); };
  o.carve.near = [&](const std::vector<Vec3>& x, double, std::vector<double>& c) {
    c.resize(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) c[i] = rb - x[i].norm();
  };
  SpsrInfo info;
  const Mesh m = ReconstructSpsr(pc, o, Context(1), nullptr, &info);
  EXPECT_EQ(info.carve_only_components, 1);
  EXPECT_GT(info.carved_nodes, 0);
  EXPECT_EQ(m.V, plain.V);
  EXPECT_EQ(m.F, plain.F);
  o.carve_keep_voids = true;
  SpsrInfo kept_info;
  const Mesh kept = ReconstructSpsr(pc, o, Context(1), nullptr, &kept_info);
  EXPECT_EQ(kept_info.carve_only_components, 0);
  const Topology t = ComputeTopology(kept);
  EXPECT_EQ(t.components, 2);
  EXPECT_EQ(t.boundary_edges, 0);
  const double ball = 4.0 / 3.0 * kPi * rb * rb * rb;
  EXPECT_NEAR(Volume(kept), Volume(plain) - ball, 0.05 * ball);
}

TEST(Spsr, InwardNormalsThroughReconstructPoissonGiveTheSameOutwardSurface) {
  PointCloud pc = SpherePoints(2000, 0.5, Vec3::Zero(), 4);
  PoissonOptions o;
  o.backend = PoissonOptions::Backend::kArcs;
  o.depth = 10;
  o.scale = 3.2;
  o.point_weight = 10;
  const Mesh out = ReconstructPoisson(pc, o, Context(1));
  pc.N = -pc.N;
  const Mesh in = ReconstructPoisson(pc, o, Context(1));
  EXPECT_GT(Volume(out), 0);
  EXPECT_NEAR(Volume(in), Volume(out), 0.02 * Volume(out));
}

TEST(Spsr, RefusesBadInput) {
  PointCloud pc = SpherePoints(100, 0.5, Vec3::Zero(), 1);
  const Context ctx(1);
  PointCloud few = pc;
  few.P.conservativeResize(5, 3);
  few.N.conservativeResize(5, 3);
  EXPECT_THROW(ReconstructSpsr(few, SpsrOptions{}, ctx), Error);
  PointCloud nan = pc;
  nan.P(17, 1) = std::numeric_limits<double>::quiet_NaN();
  try {
    ReconstructSpsr(nan, SpsrOptions{}, ctx);
    FAIL() << "NaN accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("point 17"), std::string::npos) << e.what();
  }
  PointCloud zero = pc;
  zero.N.row(3).setZero();
  EXPECT_THROW(ReconstructSpsr(zero, SpsrOptions{}, ctx), Error);
  PointCloud nonormals = pc;
  nonormals.N.resize(0, 3);
  EXPECT_THROW(ReconstructSpsr(nonormals, SpsrOptions{}, ctx), Error);
  PointCloud same = pc;
  for (int i = 0; i < same.Size(); ++i) same.P.row(i) = Eigen::RowVector3d(1, 2, 3);
  EXPECT_THROW(ReconstructSpsr(same, SpsrOptions{}, ctx), Error);
  SpsrOptions bad;
  bad.depth = 13;
  EXPECT_THROW(ReconstructSpsr(pc, bad, ctx), OptionError);
  bad = SpsrOptions{};
  bad.scale = 1.0;
  EXPECT_THROW(ReconstructSpsr(pc, bad, ctx), OptionError);
}

}  // namespace
}  // namespace arcs
