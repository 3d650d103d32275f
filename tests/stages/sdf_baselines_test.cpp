// The SDF -> mesh baselines (dual_contouring, dcsdd, vdb_mesher,
// power_diagram) through the registry: each is listed as an sdf_to_mesh
// stage, reconstructs a built-in shape, is deterministic at 1 and 2 threads,
// and refuses bad samples with an error that names it. On the bench's CAD
// meshes DC's Hausdorff distance is below marching cubes' (issue 12, item 3).
#include "framework/eval/metrics.h"
#include "framework/geometry/builtin_shapes.h"
#include "framework/geometry/marching_cubes.h"
#include "framework/geometry/normalize.h"
#include "framework/io/mesh_io.h"
#include "framework/sdf/sdf_sampling.h"
#include "framework/sdfmesh/power_diagram.h"
#include "framework/sdfmesh/vdb_mesher.h"
#include "framework/spatial/topology.h"
#include "framework/util/parallel.h"
#include "registry/registry.h"
#include "stages/builtin.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace arcs {
namespace {

const std::vector<std::string> kStages = {"dual_contouring", "dcsdd", "vdb_mesher", "power_diagram"};

bool Available(const std::string& name) {
  if (name == "vdb_mesher") return VdbMesherAvailable();
  if (name == "power_diagram") return PowerDiagramAvailable();
  return true;
}

Registry& Builtins() {
  static Registry r = [] {
    Registry x;
    RegisterBuiltinStages(x);
    return x;
  }();
  return r;
}

ParamMap Given(const std::string& name) {
  ParamMap p;
  if (name == "dcsdd") p.Set("iterations", std::int64_t{10});  // the default 100 is slow for a unit test
  return p;
}

Mesh RunMethod(const std::string& name, const SdfSamples& s, std::uint64_t seed = 1) {
  const Registry& r = Builtins();
  CaseData d;
  d.registry = &r;
  d.samples = s;
  Context ctx(seed);
  r.Get(name).factory(r.Resolve(name, Given(name)))->Run(ctx, d);
  if (!d.output) throw Error(name + " wrote no mesh");
  return *d.output;
}

SdfSamples TorusSamples(int n) {
  Context ctx(1);
  SdfGridOptions o;
  o.n = n;
  return SampleSdfGrid(MakeBuiltinShape("torus"), o, ctx);
}

TEST(SdfBaselinesTest, ListedAsSdfToMeshStagesWithDocs) {
  for (const auto& name : kStages) {
    const StageInfo& s = Builtins().Get(name);
    EXPECT_EQ(s.role, Role::kSdfToMesh) << name;
    EXPECT_FALSE(s.doc.empty()) << name;
    EXPECT_FALSE(s.params.specs().empty()) << name;
  }
}

TEST(SdfBaselinesTest, EachReconstructsTheBuiltinTorusWithItsGenus) {
  const SdfSamples s = TorusSamples(20);
  for (const auto& name : kStages) {
    if (!Available(name)) {
      std::printf("%s: skipped (library not built in)\n", name.c_str());
      continue;
    }
    const Mesh m = RunMethod(name, s);
    const Topology t = ComputeTopology(m);
    EXPECT_TRUE(t.closed) << name;
    EXPECT_EQ(t.genus, 1) << name;
    EXPECT_GT(t.volume, 0.0) << name << ": faces wound outward";
    const double chamfer = ChamferPaper(m, MakeBuiltinShape("torus"), 100000);
    EXPECT_LT(chamfer, 0.04) << name << " chamfer " << chamfer;  // h = 0.1
  }
}

TEST(SdfBaselinesTest, SameMeshAtOneAndTwoThreads) {
  const SdfSamples s = TorusSamples(16);
  for (const auto& name : kStages) {
    if (!Available(name)) continue;
    Mesh a, b;
    {
      ThreadLimit l(1);
      a = RunMethod(name, s, 5);
    }
    {
      ThreadLimit l(2);
      b = RunMethod(name, s, 5);
    }
    EXPECT_EQ(a.V, b.V) << name;
    EXPECT_EQ(a.F, b.F) << name;
  }
}

void ExpectStageError(const std::string& name, const SdfSamples& s, const std::string& part) {
  try {
    RunMethod(name, s);
    ADD_FAILURE() << name << ": no error (" << part << ")";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(name), std::string::npos) << msg;
    EXPECT_NE(msg.find(part), std::string::npos) << msg;
  }
}

TEST(SdfBaselinesTest, BadSamplesAreClearErrors) {
  const SdfSamples good = TorusSamples(6);
  for (const auto& name : kStages) {
    if (!Available(name)) continue;
    SdfSamples s = good;
    s.values = s.values.cwiseAbs().array() + 0.01;
    ExpectStageError(name, s, "no surface");
    s = good;
    s.values[11] = NAN;
    ExpectStageError(name, s, "non-finite");
    s = SdfSamples{};
    s.points = MatrixXd::Zero(1, 3);
    s.values = VectorXd::Constant(1, -0.5);
    ExpectStageError(name, s, "at least 2");
    s = good;
    s.values.conservativeResize(good.Size() - 3);
    ExpectStageError(name, s, std::to_string(good.Size() - 3) + " values");
  }
  // Scattered samples: only the power diagram takes them.
  SdfSamples scattered = good;
  scattered.grid.reset();
  for (const auto& name : {"dual_contouring", "dcsdd", "vdb_mesher"}) ExpectStageError(name, scattered, "regular grid");
  if (PowerDiagramAvailable()) {
    EXPECT_TRUE(ComputeTopology(RunMethod("power_diagram", scattered)).closed);
  }
}

// Issue 12, item 3: on the CAD-like bench meshes (paper protocol: longest
// side 1, centred, SDF on linspace(-1, 1, n + 1)^3), the mean Hausdorff
// distance of dual contouring is below marching cubes' at n = 20 and 40.
TEST(SdfBaselinesTest, DualContouringHausdorffBelowMarchingCubesOnCadMeshes) {
  ARCS_REQUIRE_SHARED_DATA();
  const std::vector<std::string> names = {"fandisk", "rocker_arm", "joint", "couplingdown"};
  for (int n : {20, 40}) {
    double dc_sum = 0, mc_sum = 0;
    for (const auto& name : names) {
      Mesh ref = ReadMesh(testing::SharedData("bench/" + name + ".obj"));
      Normalize(&ref, NormalizeOptions{});
      Context ctx(1);
      SdfGridOptions o;
      o.n = n;
      const SdfSamples s = SampleSdfGrid(ref, o, ctx);
      const double dc = HausdorffPaper(RunMethod("dual_contouring", s), ref);
      const double mc = HausdorffPaper(MarchingCubes(s.values, *s.grid), ref);
      std::printf("n=%d %-12s hausdorff DC %.4f MC %.4f\n", n, name.c_str(), dc, mc);
      dc_sum += dc;
      mc_sum += mc;
    }
    std::printf("n=%d mean hausdorff DC %.4f MC %.4f\n", n, dc_sum / names.size(), mc_sum / names.size());
    EXPECT_LT(dc_sum, mc_sum) << "n = " << n;
  }
}

}  // namespace
}  // namespace arcs
