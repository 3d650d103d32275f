// The RFTA paper's evaluation protocol end to end, checked against the
// official implementation's measured marching-cubes rows
// (../shared/reference/official_rfta_measured.csv, columns mc_chamfer,
// mc_hausdorff, mc_e_sdf): normalise (longest bbox side 1, centred), sample
// the exact SDF at the (n+1)^3 nodes of linspace(-1, 1, n+1)^3 with the sign
// from the winding number, marching cubes, then Chamfer (10^6 samples),
// Hausdorff (vertices) and E_SDF. Our marching cubes, sampling and metrics
// must reproduce libigl/gpytoolbox's numbers within 5%.
#include "framework/eval/metrics.h"

#include "framework/geometry/builtin_shapes.h"
#include "framework/geometry/marching_cubes.h"
#include "framework/geometry/normalize.h"
#include "framework/spatial/triangle_bvh.h"
#include "framework/spatial/winding_number.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace arcs {
namespace {

// The protocol's grid SDF. (arcs_eval does not link arcs_sdf, so this is the
// few lines of SampleSdfGrid again, from the same spatial primitives.)
SdfSamples GridSdf(const Mesh& mesh, int n) {
  const int m = n + 1;
  SdfSamples s;
  GridInfo g;
  g.dim = 3;
  g.dims = {m, m, m};
  g.min = {-1, -1, -1};
  g.max = {1, 1, 1};
  MatrixX3d P(g.NumNodes(), 3);
  for (int k = 0; k < m; ++k) {
    for (int j = 0; j < m; ++j) {
      for (int i = 0; i < m; ++i) {
        P.row(i + m * (j + m * k)) << -1.0 + 2.0 * i / n, -1.0 + 2.0 * j / n, -1.0 + 2.0 * k / n;
      }
    }
  }
  VectorXd sq;
  TriangleBvh(mesh).ClosestPoints(P, &sq);
  const VectorXd w = FastWindingNumber(mesh).Eval(P);
  s.values.resize(P.rows());
  for (Eigen::Index i = 0; i < P.rows(); ++i) {
    s.values[i] = w[i] > 0.5 ? -std::sqrt(sq[i]) : std::sqrt(sq[i]);
  }
  s.points = P;
  s.grid = g;
  return s;
}

// Minimal OBJ reader (v and f lines; polygons fanned).
Mesh ReadObj(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  std::vector<double> v;
  std::vector<int> f;
  std::string line;
  while (std::getline(in, line)) {
    if (line.size() < 2 || line[1] != ' ') continue;
    std::istringstream ss(line.substr(2));
    if (line[0] == 'v') {
      double x, y, z;
      ss >> x >> y >> z;
      v.insert(v.end(), {x, y, z});
    } else if (line[0] == 'f') {
      std::vector<int> idx;
      std::string t;
      while (ss >> t) idx.push_back(std::stoi(t.substr(0, t.find('/'))) - 1);
      for (std::size_t k = 1; k + 1 < idx.size(); ++k) f.insert(f.end(), {idx[0], idx[k], idx[k + 1]});
    }
  }
  Mesh m;
  m.V.resize(static_cast<Eigen::Index>(v.size() / 3), 3);
  m.F.resize(static_cast<Eigen::Index>(f.size() / 3), 3);
  for (std::size_t i = 0; i < v.size(); ++i) m.V(i / 3, i % 3) = v[i];
  for (std::size_t i = 0; i < f.size(); ++i) m.F(i / 3, i % 3) = f[i];
  return m;
}

struct McRow {
  double chamfer, hausdorff, e_sdf;
};

McRow RunMcProtocol(Mesh gt, int n) {
  Normalize(&gt, NormalizeOptions{});
  const SdfSamples s = GridSdf(gt, n);
  const Mesh mc = MarchingCubes(s.values, *s.grid);
  return {ChamferPaper(gt, mc, 1000000, 1), HausdorffPaper(gt, mc), EnergySdf(s, mc)};
}

void ExpectWithin(double got, double want, double rel, const char* what) {
  EXPECT_NEAR(got / want, 1.0, rel) << what << ": got " << got << ", official " << want;
}

TEST(ProtocolTest, TorusN20MatchesOfficialMarchingCubes) {
  // torus,20,...: mc_chamfer 0.01542, mc_hausdorff 0.0187, mc_e_sdf 3.8e-2.
  // (Ours, measured: 0.01539, 0.01866, 0.03754.)
  const McRow r = RunMcProtocol(MakeTorus(0.35, 0.15, 400, 200), 20);
  ExpectWithin(r.chamfer, 0.01542, 0.05, "mc_chamfer");
  ExpectWithin(r.hausdorff, 0.0187, 0.05, "mc_hausdorff");
  ExpectWithin(r.e_sdf, 3.8e-2, 0.05, "mc_e_sdf");
}

TEST(ProtocolTest, ChamferFloorOfTorusMatchesOfficial) {
  // "GT torus vs itself: 0.00514 with 1e5 samples" (1e6: 0.00163, ours 0.00162).
  Mesh t = MakeTorus(0.35, 0.15, 400, 200);
  Normalize(&t, NormalizeOptions{});
  ExpectWithin(ChamferPaper(t, t, 100000, 1), 0.00514, 0.05, "chamfer floor 1e5");
}

TEST(ProtocolTest, BunnyN20MatchesOfficialMarchingCubes) {
  ARCS_REQUIRE_SHARED_DATA();
  // bunny_fixed,20,...: mc_chamfer 0.0450, mc_hausdorff 0.1882, mc_e_sdf 3.6.
  // (Ours, measured: 0.04513, 0.18815, 3.607.)
  const McRow r = RunMcProtocol(ReadObj(testing::SharedData("bench/bunny_fixed.obj")), 20);
  ExpectWithin(r.chamfer, 0.0450, 0.05, "mc_chamfer");
  ExpectWithin(r.hausdorff, 0.1882, 0.05, "mc_hausdorff");
  ExpectWithin(r.e_sdf, 3.6, 0.05, "mc_e_sdf");
}

}  // namespace
}  // namespace arcs
