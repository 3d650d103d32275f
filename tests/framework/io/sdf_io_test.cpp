#include "framework/io/sdf_io.h"

#include "framework/error.h"
#include "framework/io/npy.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

namespace arcs {
namespace {

namespace fs = std::filesystem;

using testing::WriteFile;


// numpy.linspace(a, b, n)[i] as numpy computes it.
double Lin(double a, double b, int n, int i) {
  if (i == n - 1) return b;
  return i * ((b - a) / (n - 1)) + a;
}

double F3(double x, double y, double z) { return x + 10 * y + 100 * z; }

// Writes arr[i, j, k] = F3(x_i, y_j, z_k) in numpy C order.
void WriteGrid3(const std::string& path, int nx, int ny, int nz, std::array<double, 3> lo,
                std::array<double, 3> hi) {
  std::vector<double> v;
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j)
      for (int k = 0; k < nz; ++k)
        v.push_back(F3(Lin(lo[0], hi[0], nx, i), Lin(lo[1], hi[1], ny, j), Lin(lo[2], hi[2], nz, k)));
  WriteNpy(path, v.data(), {nx, ny, nz});
}

TEST(SdfIoTest, Grid3dIsReorderedToXFastestWithLinspacePoints) {
  const auto dir = testing::TempDir("sdf_io_grid3");
  const std::string path = (dir / "g.npy").string();
  const std::array<double, 3> lo{-0.5, -1, 0.1}, hi{0.5, 2, 0.7};
  WriteGrid3(path, 3, 4, 5, lo, hi);
  const SdfSamples s = ReadSdfGrid(path, lo, hi);
  ASSERT_TRUE(s.grid.has_value());
  EXPECT_EQ(s.dim, 3);
  EXPECT_EQ(s.grid->dims, (std::array<int, 3>{3, 4, 5}));
  EXPECT_EQ(s.grid->min, lo);
  EXPECT_EQ(s.grid->max, hi);
  ASSERT_EQ(s.Size(), 60);
  ASSERT_EQ(s.points.cols(), 3);
  for (int k = 0; k < 5; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 3; ++i) {
        const int idx = i + 3 * (j + 4 * k);
        EXPECT_EQ(s.points(idx, 0), Lin(lo[0], hi[0], 3, i));
        EXPECT_EQ(s.points(idx, 1), Lin(lo[1], hi[1], 4, j));
        EXPECT_EQ(s.points(idx, 2), Lin(lo[2], hi[2], 5, k));
        EXPECT_EQ(s.values[idx], F3(s.points(idx, 0), s.points(idx, 1), s.points(idx, 2)));
      }
  EXPECT_EQ(s.points(59, 2), 0.7);  // endpoint exactly max
}

TEST(SdfIoTest, BoundsSidecarOverridesDefaultsAndWriteReadRoundTrips) {
  const auto dir = testing::TempDir("sdf_io_sidecar");
  const std::string path = (dir / "g.npy").string();
  WriteGrid3(path, 2, 3, 2, {0, 0, 0}, {1, 2, 3});
  WriteFile(SdfBoundsPath(path), "# bounds\n0 0 0\n1 2 3\n");
  const SdfSamples s = ReadSdfGrid(path);  // defaults [-1,1]^3 overridden
  EXPECT_EQ(s.grid->max, (std::array<double, 3>{1, 2, 3}));
  EXPECT_EQ(s.points(s.Size() - 1, 1), 2.0);
  for (int i = 0; i < s.Size(); ++i)
    EXPECT_EQ(s.values[i], F3(s.points(i, 0), s.points(i, 1), s.points(i, 2)));

  // Write -> read is exact, and the sidecar comes along.
  const std::string out = (dir / "out.npy").string();
  SdfSamples t = s;
  t.grid->min = {-0.1, 1.0 / 3.0, -7};
  t.grid->max = {0.3, 2.5, 1e-3};
  WriteSdfGrid(out, t);
  ASSERT_TRUE(fs::exists(SdfBoundsPath(out)));
  const SdfSamples r = ReadSdfGrid(out);
  EXPECT_EQ(r.grid->dims, t.grid->dims);
  EXPECT_EQ(r.grid->min, t.grid->min);
  EXPECT_EQ(r.grid->max, t.grid->max);
  EXPECT_TRUE(r.values == t.values);
  EXPECT_EQ(ReadNpy(out).shape, (std::vector<std::int64_t>{2, 3, 2}));

  WriteFile(SdfBoundsPath(path), "0 0 0 1 2\n");
  testing::ExpectInputError([&] { ReadSdfGrid(path); }, {SdfBoundsPath(path), "found 5 numbers"});
  WriteFile(SdfBoundsPath(path), "0 0 0\n1 nan 3\n");
  testing::ExpectInputError([&] { ReadSdfGrid(path); }, {SdfBoundsPath(path) + ":2:", "bad bound"});
  WriteFile(SdfBoundsPath(path), "0 0 0 1 0 3\n");
  testing::ExpectInputError([&] { ReadSdfGrid(path); }, {path, "min < max on axis 1"});
}

TEST(SdfIoTest, Grid2d) {
  const auto dir = testing::TempDir("sdf_io_grid2");
  const std::string path = (dir / "g2.npy").string();
  std::vector<double> v;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 7; ++j) v.push_back(Lin(-1, 1, 5, i) - 3 * Lin(-1, 1, 7, j));
  WriteNpy(path, v.data(), {5, 7});
  const SdfSamples s = ReadSdfGrid(path);
  EXPECT_EQ(s.dim, 2);
  EXPECT_EQ(s.grid->dim, 2);
  EXPECT_EQ(s.grid->dims, (std::array<int, 3>{5, 7, 1}));
  ASSERT_EQ(s.points.cols(), 2);
  ASSERT_EQ(s.Size(), 35);
  for (int i = 0; i < 35; ++i) EXPECT_EQ(s.values[i], s.points(i, 0) - 3 * s.points(i, 1));
  EXPECT_EQ(s.points(1, 0), -0.5);  // x fastest
  const std::string out = (dir / "o2.npy").string();
  WriteSdfGrid(out, s);
  const SdfSamples r = ReadSdf(out);  // (5, 7): a 2D grid by the dispatch rule
  EXPECT_TRUE(r.values == s.values);
  EXPECT_TRUE(r.points == s.points);
}

TEST(SdfIoTest, GridRejectsNonFiniteValuesAndBadShapes) {
  const auto dir = testing::TempDir("sdf_io_grid_bad");
  const std::string path = (dir / "g.npy").string();
  std::vector<double> v(2 * 2 * 2, 0.5);
  v[(1 * 2 + 0) * 2 + 1] = std::nan("");
  WriteNpy(path, v.data(), {2, 2, 2});
  testing::ExpectInputError([&] { ReadSdfGrid(path); }, {path, "grid index (1, 0, 1)", "not finite"});
  WriteNpy(path, v.data(), {8});
  testing::ExpectInputError([&] { ReadSdfGrid(path); }, {path, "(nx, ny, nz) or (nx, ny)", "(8,)"});
}

TEST(SdfIoTest, ScatteredPairAndErrors) {
  const auto dir = testing::TempDir("sdf_io_scattered");
  const std::string pp = (dir / "p.npy").string(), vp = (dir / "v.npy").string();
  const std::vector<double> P = {0.1, 0.2, 0.3, -1, -2, -3, 1e-9, 0, 5};
  const std::vector<double> V = {0.25, -0.5, 1.0 / 7.0};
  WriteNpy(pp, P.data(), {3, 3});
  WriteNpy(vp, V.data(), {3, 1});
  const SdfSamples s = ReadSdfScattered(pp, vp);
  EXPECT_EQ(s.dim, 3);
  EXPECT_FALSE(s.grid.has_value());
  ASSERT_EQ(s.Size(), 3);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(s.values[i], V[i]);
    for (int a = 0; a < 3; ++a) EXPECT_EQ(s.points(i, a), P[3 * i + a]);
  }
  // 2D points, (N,) values.
  WriteNpy(pp, P.data(), {3, 2});  // uses the first 6 numbers
  WriteNpy(vp, V.data(), {3});
  const SdfSamples s2 = ReadSdfScattered(pp, vp);
  EXPECT_EQ(s2.dim, 2);
  EXPECT_EQ(s2.points(2, 1), P[5]);

  WriteNpy(vp, V.data(), {2});
  testing::ExpectInputError([&] { ReadSdfScattered(pp, vp); }, {vp, pp, "has 2 values", "has 3 points"});
  std::vector<double> W = V;
  W[1] = -INFINITY;
  WriteNpy(vp, W.data(), {3});
  testing::ExpectInputError([&] { ReadSdfScattered(pp, vp); }, {vp, "sample 1", "not finite"});
  WriteNpy(pp, P.data(), {9});
  testing::ExpectInputError([&] { ReadSdfScattered(pp, vp); }, {pp, "(N, 3) or (N, 2)"});
}

TEST(SdfIoTest, TextReadWriteAndErrors) {
  const auto dir = testing::TempDir("sdf_io_text");
  const std::string path = (dir / "s.txt").string();
  WriteFile(path, "# x y z s\n\n0 0 0 -0.5\n  1 2 3 0.25 # comment\r\n1e-3 -2 +3 7\n");
  const SdfSamples s = ReadSdfText(path);
  EXPECT_EQ(s.dim, 3);
  ASSERT_EQ(s.Size(), 3);
  EXPECT_EQ(s.values[1], 0.25);
  EXPECT_EQ(s.points(2, 0), 1e-3);
  EXPECT_EQ(s.points(2, 2), 3.0);

  const std::string p2 = (dir / "s2.xyzs").string();
  WriteFile(p2, "0 0 1\n0.5 0.5 -1\n");
  const SdfSamples t = ReadSdf(p2);
  EXPECT_EQ(t.dim, 2);
  EXPECT_EQ(t.Size(), 2);

  // Round trip through text is exact.
  SdfSamples u;
  u.dim = 3;
  u.points.resize(2, 3);
  u.points << 1.0 / 3.0, -M_PI, 1e-310, 0.1, 0.2, 0.3;
  u.values.resize(2);
  u.values << -1e300, 2.0 / 3.0;
  const std::string p3 = (dir / "u.sdf").string();
  WriteSdfText(p3, u);
  const SdfSamples w = ReadSdf(p3);
  EXPECT_TRUE(w.points == u.points);
  EXPECT_TRUE(w.values == u.values);

  struct Case {
    std::string body;
    std::string where;
    std::string what;
  };
  const std::vector<Case> cases = {
      {"0 0 0 1\n1 1 1\n", ":2:", "first sample line has 4"},
      {"# only\n0 0 0 1 5\n", ":2:", "found 5 columns"},
      {"0 0 0 1\n\n0 0 nan 1\n", ":3:", "non-finite"},
      {"0 0 0 1\n0 0 zero 1\n", ":2:", "bad number 'zero'"},
      {"# nothing\n\n", ": ", "no samples"},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const std::string p = (dir / ("bad" + std::to_string(i) + ".txt")).string();
    WriteFile(p, cases[i].body);
    testing::ExpectInputError([&] { ReadSdfText(p); }, {p + cases[i].where, cases[i].what});
  }
}

TEST(SdfIoTest, ReadSdfDispatchRule) {
  const auto dir = testing::TempDir("sdf_io_dispatch");
  // (N, 4): scattered 3D samples.
  const std::vector<double> a = {0, 0, 0, -1, 1, 1, 1, 2};
  const std::string p4 = (dir / "n4.npy").string();
  WriteNpy(p4, a.data(), {2, 4});
  SdfSamples s = ReadSdf(p4);
  EXPECT_EQ(s.dim, 3);
  EXPECT_FALSE(s.grid.has_value());
  EXPECT_EQ(s.values[1], 2.0);
  EXPECT_EQ(s.points(1, 2), 1.0);
  // (N, 3): scattered 2D.
  const std::string p3 = (dir / "n3.npy").string();
  WriteNpy(p3, a.data(), {2, 3});
  s = ReadSdf(p3);
  EXPECT_EQ(s.dim, 2);
  EXPECT_EQ(s.values[0], 0.0);
  EXPECT_EQ(s.values[1], 1.0);
  EXPECT_EQ(s.points(1, 0), -1.0);
  // (N, 3) with a bounds sidecar: a 2D grid.
  WriteFile(SdfBoundsPath(p3), "0 0 1 1\n");
  s = ReadSdf(p3);
  ASSERT_TRUE(s.grid.has_value());
  EXPECT_EQ(s.grid->dims, (std::array<int, 3>{2, 3, 1}));
  // ndim 3: a 3D grid with default bounds.
  const std::string g = (dir / "g.npy").string();
  WriteGrid3(g, 2, 2, 2, {-1, -1, -1}, {1, 1, 1});
  s = ReadSdf(g);
  ASSERT_TRUE(s.grid.has_value());
  EXPECT_EQ(s.grid->min, (std::array<double, 3>{-1, -1, -1}));
  EXPECT_EQ(s.values[7], F3(1, 1, 1));
  // Other shapes and extensions: errors that explain.
  const std::string p1 = (dir / "one.npy").string();
  WriteNpy(p1, a.data(), {8});
  testing::ExpectInputError([&] { ReadSdf(p1); }, {p1, "(8,)", "(nx, ny, nz)", "(N, 4)"});
  const std::string vtk = (dir / "x.vtk").string();
  WriteFile(vtk, "");
  testing::ExpectInputError([&] { ReadSdf(vtk); }, {vtk, ".npy, .npz, .txt"});
  std::vector<double> bad = a;
  bad[6] = std::nan("");
  WriteNpy(p4, bad.data(), {2, 4});
  testing::ExpectInputError([&] { ReadSdf(p4); }, {p4, "sample 1", "non-finite"});
}

}  // namespace
}  // namespace arcs
