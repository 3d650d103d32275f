#include "framework/sdfmesh/sdf_input.h"

#include "framework/error.h"
#include "tests/framework/sdfmesh/sdfmesh_test_fields.h"

#include <gtest/gtest.h>

#include <cmath>

namespace arcs {
namespace {

using testing::GridSamples;
using testing::SphereSdf;

void ExpectError(const SdfSamples& s, bool grid, const std::vector<std::string>& parts) {
  try {
    CheckSdfToMeshInput(s, "some_stage", grid);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind("some_stage: ", 0), 0u) << msg;
    for (const auto& p : parts) EXPECT_NE(msg.find(p), std::string::npos) << msg;
  }
}

TEST(SdfInputTest, GoodGridAndScatteredSamplesPass) {
  SdfSamples s = GridSamples(4, -1, 1, [](const Vec3& p) { return SphereSdf(p, 0.5); });
  EXPECT_NO_THROW(CheckSdfToMeshInput(s, "x", true));
  s.grid.reset();
  EXPECT_NO_THROW(CheckSdfToMeshInput(s, "x", false));
}

TEST(SdfInputTest, EachDefectIsNamed) {
  const SdfSamples good = GridSamples(4, -1, 1, [](const Vec3& p) { return SphereSdf(p, 0.5); });
  SdfSamples s = good;
  s.values.setConstant(0.3);
  ExpectError(s, true, {"all 125", "outside", "no surface"});
  s.values.setConstant(-0.3);
  ExpectError(s, true, {"inside", "no surface"});
  s = good;
  s.values[17] = NAN;
  ExpectError(s, true, {"sample 17", "non-finite value"});
  s = good;
  s.points(3, 1) = INFINITY;
  ExpectError(s, false, {"sample 3", "non-finite coordinate"});
  s = good;
  s.values.conservativeResize(100);
  ExpectError(s, false, {"125 points", "100 values"});
  s = good;
  s.points.conservativeResize(100, 3);
  s.values.conservativeResize(100);
  ExpectError(s, true, {"125 nodes", "100 values"});
  s = SdfSamples{};
  s.points = MatrixXd::Zero(1, 3);
  s.values = VectorXd::Constant(1, -0.1);
  ExpectError(s, false, {"at least 2", "got 1"});
  s = good;
  s.grid.reset();
  ExpectError(s, true, {"regular grid", "scattered"});
  s = good;
  s.dim = 2;
  ExpectError(s, false, {"3D"});
}

}  // namespace
}  // namespace arcs
