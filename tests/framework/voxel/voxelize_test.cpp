// Winding-number voxelization: fast vs exact signs, open meshes, degenerate
// input (framework/voxel/voxelize.h). Built-in shapes only (no shared data).
#include "framework/error.h"
#include "framework/geometry/builtin_shapes.h"
#include "framework/spatial/winding_number.h"
#include "framework/voxel/doph_protocol.h"
#include "framework/voxel/ray_parity.h"
#include "framework/voxel/voxelize.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace arcs {
namespace {

GridInfo Grid(int r, double h = 0.6) { return CubeGrid(r, Vec3::Constant(-h), Vec3::Constant(h)); }

std::int64_t Differences(const VectorXd& a, const VectorXd& b) {
  std::int64_t n = 0;
  for (std::int64_t i = 0; i < a.size(); ++i) n += (a[i] > 0.5) != (b[i] > 0.5);
  return n;
}

Mesh Flipped(Mesh m) {
  for (int f = 0; f < m.NumFaces(); ++f) std::swap(m.F(f, 1), m.F(f, 2));
  return m;
}

// A flat disc of radius R at height z: rings x sectors, fan-triangulated.
Mesh Disc(double R, double z, int rings = 8, int sectors = 32) {
  Mesh m;
  m.V.resize(1 + rings * sectors, 3);
  m.V.row(0) << 0.0123, -0.0071, z;
  for (int r = 1; r <= rings; ++r)
    for (int s = 0; s < sectors; ++s) {
      const double a = 2 * std::numbers::pi * (s + 0.37) / sectors, rad = R * r / rings;
      m.V.row(1 + (r - 1) * sectors + s) << rad * std::cos(a), rad * std::sin(a), z;
    }
  std::vector<std::array<int, 3>> F;
  for (int s = 0; s < sectors; ++s) F.push_back({0, 1 + s, 1 + (s + 1) % sectors});
  for (int r = 1; r < rings; ++r)
    for (int s = 0; s < sectors; ++s) {
      const int a = 1 + (r - 1) * sectors + s, b = 1 + (r - 1) * sectors + (s + 1) % sectors;
      const int c = a + sectors, d = b + sectors;
      F.push_back({a, c, d});
      F.push_back({a, d, b});
    }
  m.F.resize(static_cast<int>(F.size()), 3);
  for (std::size_t i = 0; i < F.size(); ++i) m.F.row(static_cast<int>(i)) << F[i][0], F[i][1], F[i][2];
  return m;
}

TEST(Voxelize, FastAgreesInSignWithExactOnBuiltinShapes) {
  const std::vector<std::pair<std::string, Mesh>> shapes = {
      {"torus", MakeTorus(0.35, 0.15, 40, 20)},
      {"knot", MakeTorusKnot(2, 3, 0.3, 0.12, 0.06, 120, 10)},
      {"sphere", MakeIcosphere(0.45, 3, Vec3(0.01, -0.02, 0.03))},
      {"two_spheres", Concatenate({MakeIcosphere(0.2, 2, Vec3(-0.25, 0, 0)), MakeIcosphere(0.2, 2, Vec3(0.25, 0.01, 0))})}};
  for (const auto& [name, m] : shapes) {
    const GridInfo g = Grid(20);
    VoxelizeOptions fast, exact;
    exact.method = "exact";
    VoxelizeReport rf;
    const VolumeGrid vf = Voxelize(m, g, fast, &rf);
    const VolumeGrid ve = Voxelize(m, g, exact);
    EXPECT_EQ(rf.path, "flood_fill") << name;
    EXPECT_EQ(Differences(vf.values, ve.values), 0) << name;
    EXPECT_GT(rf.occupied, 10) << name;
    // The grid is split into more than inside/outside only near the surface.
    EXPECT_LT(rf.components, g.NumNodes() / 4) << name;
    // Winding output: the component's exact value, integers off the surface.
    fast.output = "winding";
    const VolumeGrid wf = Voxelize(m, g, fast);
    for (std::int64_t i = 0; i < wf.values.size(); ++i) ASSERT_TRUE(std::isfinite(wf.values[i]));
  }
}

TEST(Voxelize, NodesOnTheSurfaceAndInwardOrientation) {
  // A box-like octahedron whose vertices sit exactly on grid nodes.
  const Mesh s = MakeIcosphere(0.5, 0);  // vertices on the axes? not in general; use a scaled copy
  const GridInfo g = Grid(13, 0.6);      // nodes at multiples of 0.1
  Mesh oct;
  oct.V.resize(6, 3);
  oct.V << 0.5, 0, 0, -0.5, 0, 0, 0, 0.5, 0, 0, -0.5, 0, 0, 0, 0.5, 0, 0, -0.5;
  oct.F.resize(8, 3);
  oct.F << 0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5;
  for (const Mesh* m : std::vector<const Mesh*>{&oct, &s}) {
    VoxelizeOptions exact;
    exact.method = "exact";
    const VolumeGrid ve = Voxelize(*m, g, exact);
    const VolumeGrid vf = Voxelize(*m, g, {});
    EXPECT_EQ(Differences(vf.values, ve.values), 0);
    // Inward orientation: |w| keeps the solid (nodes exactly on a face, w =
    // +-1/2 up to rounding, may differ); as_is gives nothing inside.
    const VolumeGrid vi = Voxelize(Flipped(*m), g, {});
    EXPECT_EQ(Differences(vi.values, Voxelize(Flipped(*m), g, exact).values), 0);
    if (m == &s) {
      EXPECT_EQ(Differences(vi.values, ve.values), 0);
    }
    VoxelizeOptions as_is;
    as_is.orientation = "as_is";
    EXPECT_EQ(Voxelize(Flipped(*m), g, as_is).values.sum(), 0.0);
  }
}

TEST(Voxelize, HolesPunchedSolidStaysSolid) {
  const Mesh closed = MakeIcosphere(0.5, 4);  // 5120 faces, size 1
  const Mesh holed = PunchHoles(closed, SpreadVertices(closed, 6), 0.05);
  ASSERT_LT(holed.NumFaces(), closed.NumFaces());
  ASSERT_GT(CountUnbalancedEdges(holed), 0);
  const GridInfo g = Grid(40);
  const VolumeGrid vc = Voxelize(closed, g, {});
  VoxelizeReport rep;
  const VolumeGrid vh = Voxelize(holed, g, {}, &rep);
  EXPECT_EQ(rep.path, "hierarchy");
  const double oc = vc.values.sum(), oh = vh.values.sum();
  EXPECT_GT(oc, 1000);
  EXPECT_LT(std::abs(oh - oc) / oc, 0.01) << oc << " vs " << oh;
  EXPECT_LT(rep.sheet_faces, holed.NumFaces() / 20);
  // The paper's Alg. 2 maps the inside of the leaky solid to "outside".
  VoxelizeOptions fd;
  fd.open_mesh = "flip_dup";
  EXPECT_LT(Voxelize(holed, g, fd).values.sum(), 0.5 * oc);
}

TEST(Voxelize, OpenDiscBecomesThinShell) {
  const double z = 0.0137;
  const Mesh disc = Disc(0.45, z);
  const GridInfo g = Grid(40);
  const double h = 1.2 / 39;
  VoxelizeOptions none;
  none.open_mesh = "none";
  EXPECT_EQ(Voxelize(disc, g, none).values.sum(), 0.0);  // |w| < 1/2 off the sheet
  VoxelizeReport rep;
  const VolumeGrid v = Voxelize(disc, g, {}, &rep);
  EXPECT_EQ(rep.sheet_faces, disc.NumFaces());
  const MatrixX3d Q = GridNodes(g);
  std::int64_t near = 0, near_in = 0, far_in = 0;
  for (std::int64_t i = 0; i < Q.rows(); ++i) {
    const double r = std::hypot(Q(i, 0), Q(i, 1)), dz = std::abs(Q(i, 2) - z);
    if (r < 0.4 && dz < 0.5 * h) {
      ++near;
      near_in += v.values[i] > 0.5;
    }
    if (dz > 0.87 * h + 1e-12 || r > 0.45 + 0.87 * h + 1e-12) far_in += v.values[i] > 0.5;
  }
  EXPECT_GT(near, 100);
  EXPECT_EQ(near_in, near);  // the layer next to the disc is occupied
  EXPECT_EQ(far_in, 0);      // nothing beyond the shell thickness
  // Marching cubes of the shell: a closed thin slab.
  const Mesh shell = VolumeToMesh(v);
  EXPECT_GT(shell.NumFaces(), 100);
  EXPECT_GT(SignedVolume(shell), 0.0);
  // Alg. 2 with an offset larger than the grid step also gives a slab.
  VoxelizeOptions fd;
  fd.open_mesh = "flip_dup";
  fd.epsilon = 0.08;
  const VolumeGrid vd = Voxelize(disc, g, fd);
  std::int64_t fd_in = 0, fd_far = 0;
  for (std::int64_t i = 0; i < Q.rows(); ++i) {
    fd_in += vd.values[i] > 0.5;
    if (std::abs(Q(i, 2) - z) > 0.08 + 1e-9) fd_far += vd.values[i] > 0.5;
  }
  EXPECT_GT(fd_in, 100);
  EXPECT_EQ(fd_far, 0);
}

TEST(Voxelize, DegenerateInputNeverNaN) {
  Mesh m = MakeIcosphere(0.4, 2);
  const int nv = m.NumVertices(), nf = m.NumFaces();
  // Duplicate faces, zero-area faces, a dangling non-manifold fin, a vertex on a node.
  m.V.conservativeResize(nv + 3, 3);
  m.V.row(nv) << 0.0, 0.0, 0.0;
  m.V.row(nv + 1) << 0.1, 0.0, 0.0;
  m.V.row(nv + 2) << 0.2, 0.0, 0.0;  // collinear with the previous two
  m.F.conservativeResize(nf + 5, 3);
  m.F.row(nf) = m.F.row(0);
  m.F.row(nf + 1) = m.F.row(1);
  m.F.row(nf + 2) << nv, nv + 1, nv + 2;  // zero area
  m.F.row(nf + 3) << 0, 0, 1;             // repeated index
  m.F.row(nf + 4) << m.F(5, 0), m.F(5, 1), nv + 1;  // fin on an existing edge
  const GridInfo g = Grid(21, 0.5);  // node (0,0,0) and (0.1,0,0)... on the fin/degenerate face
  for (const std::string method : {"fast", "exact", "naive"})
    for (const std::string rule : {"auto", "none", "flip_dup"})
      for (const std::string out : {"occupancy", "winding"}) {
        VoxelizeOptions o;
        o.method = method, o.open_mesh = rule, o.output = out;
        VoxelizeReport rep;
        const VolumeGrid v = Voxelize(m, g, o, &rep);
        EXPECT_EQ(rep.dropped_faces, 2);
        for (std::int64_t i = 0; i < v.values.size(); ++i)
          ASSERT_TRUE(std::isfinite(v.values[i])) << method << " " << rule << " " << out;
        if (method != "naive" && out == "occupancy") {
          EXPECT_GT(v.values.sum(), 100) << method << " " << rule;
        }
      }
  // Empty mesh: all zero; NaN coordinates and bad indices: InputError.
  EXPECT_EQ(Voxelize(Mesh{}, g, {}).values.sum(), 0.0);
  Mesh bad = MakeIcosphere(0.4, 1);
  bad.V(3, 1) = NAN;
  EXPECT_THROW(Voxelize(bad, g, {}), InputError);
  bad = MakeIcosphere(0.4, 1);
  bad.F(2, 2) = 100000;
  EXPECT_THROW(Voxelize(bad, g, {}), InputError);
  VoxelizeOptions o;
  o.method = "magic";
  EXPECT_THROW(Voxelize(MakeIcosphere(0.4, 1), g, o), OptionError);
}

TEST(Voxelize, NaiveMatchesExactAwayFromTheSurface) {
  const Mesh m = MakeIcosphere(0.3, 3);
  MatrixX3d Q(4, 3);
  Q << 0, 0, 0, 0.1, 0.05, 0, 0.6, 0, 0, 0.5, 0.5, 0.5;
  const VectorXd wn = WindingNumbersNaive(m, Q), we = WindingNumbersExact(m, Q);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(wn[i], we[i], 0.02) << i;
  EXPECT_NEAR(we[0], 1.0, 1e-9);
}

TEST(Voxelize, RayParityAgreesOnACleanSphere) {
  if (!HaveRayParity()) GTEST_SKIP() << "built without Embree";
  const Mesh m = MakeIcosphere(0.45, 3, Vec3(0.013, -0.021, 0.007));
  const GridInfo g = Grid(24);
  VoxelizeOptions rp;
  rp.method = "ray_parity";
  const VolumeGrid a = Voxelize(m, g, rp), b = Voxelize(m, g, {});
  EXPECT_LE(Differences(a.values, b.values), 2);  // rays through edges may double-count
  EXPECT_GT(b.values.sum(), 1000);
}

TEST(Voxelize, VerifyOccupancyFindsPlantedErrors) {
  const Mesh m = MakeTorus(0.35, 0.15, 48, 24);
  const GridInfo g = Grid(24);
  VolumeGrid v = Voxelize(m, g, {});
  SignCheck sc = VerifyOccupancy(m, v, "abs", 0.1, 100, 1);
  EXPECT_EQ(sc.differences, 0);
  EXPECT_GE(sc.exact_checked, 90);
  v.values[12 + 24 * (12 + 24 * 12)] = 1.0 - v.values[12 + 24 * (12 + 24 * 12)];
  sc = VerifyOccupancy(m, v, "abs", 0.1, 0, 1);
  EXPECT_EQ(sc.differences, 1);
}

TEST(DophProtocol, SmoothingKeepsVolumeAndMetricsAreSmallOnASphere) {
  const Mesh sphere = MakeIcosphere(0.8, 4);
  const VolumeGrid v = Voxelize(sphere, CubeGrid(32, Vec3::Constant(-1), Vec3::Constant(1)), {});
  const Mesh mc = VolumeToMesh(v);
  const Mesh sm = LaplacianSmooth(mc, {});
  EXPECT_NEAR(SignedVolume(sm), SignedVolume(mc), 1e-9 * SignedVolume(mc));
  EXPECT_NEAR(SignedVolume(mc), 4.0 / 3.0 * std::numbers::pi * 0.512, 0.05);
  const DophMetrics a = ComputeDophMetrics(sm, sphere, 5000, 3, 7);
  const DophMetrics b = ComputeDophMetrics(sphere, sphere, 5000, 3, 7);
  EXPECT_GT(a.chamfer, b.chamfer);        // the sampling floor
  EXPECT_LT(a.chamfer, b.chamfer + 0.03);
  EXPECT_LT(a.hausdorff, 0.08);
  EXPECT_GT(a.chamfer_std, 0.0);
}


// Issue 15: a face far outside the grid (1e300 / h) must not reach an int
// cast out of range (UBSan) or a signed overflow; the grid stays valid.
TEST(Voxelize, FacesFarOutsideTheGridStayInBounds) {
  Mesh m = MakeBuiltinShape("sphere");
  const int nv = m.NumVertices();
  m.V.conservativeResize(nv + 3, 3);
  m.V.row(nv) = Vec3(1e300, 1e300, 1e300);
  m.V.row(nv + 1) = Vec3(-1e300, 1e300, 0);
  m.V.row(nv + 2) = Vec3(1e300, -1e300, 1e-310);
  const int nf = m.NumFaces();
  m.F.conservativeResize(nf + 1, 3);
  m.F.row(nf) << nv, nv + 1, nv + 2;
  for (const char* method : {"fast", "exact"}) {
    VoxelizeOptions o;
    o.method = method;
    const VolumeGrid g = Voxelize(m, CubeGrid(12, Vec3::Constant(-1), Vec3::Constant(1)), o);
    EXPECT_TRUE(g.values.allFinite());
    EXPECT_GT(g.values.sum(), 0.0) << method;
  }
}

}  // namespace
}  // namespace arcs
