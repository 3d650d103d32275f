// Typed dataset items (orchestration/items.h): their kinds, names and the
// keys case ids hash.
#include "orchestration/items.h"

#include "framework/error.h"

#include <gtest/gtest.h>

namespace arcs {
namespace {

std::string ErrorOf(DatasetKind k, const std::string& name) {
  try {
    BuiltinItem(k, name);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(ItemsTest, FileItemsTakeTheirKindFromTheDatasetAndTheirNameFromTheStem) {
  const DatasetItem m = FileItem(DatasetKind::kMesh, "/d/bunny_fixed.obj");
  EXPECT_EQ(m.kind, ItemKind::kMeshFile);
  EXPECT_EQ(m.name, "bunny_fixed");
  EXPECT_EQ(m.Key(), "/d/bunny_fixed.obj");
  EXPECT_FALSE(m.IsBuiltin());
  EXPECT_EQ(FileItem(DatasetKind::kPoints, "/d/scan.ply").kind, ItemKind::kPointFile);
  EXPECT_EQ(FileItem(DatasetKind::kCurves, "/d/c.obj").kind, ItemKind::kCurveFile);
  EXPECT_EQ(FileItem(DatasetKind::kCurves, "/d/c.obj").Dataset(), DatasetKind::kCurves);
}

TEST(ItemsTest, BuiltinKeysAreTheTextCaseIdsHashedBeforeItemsWereTyped) {
  const DatasetItem s = BuiltinItem(DatasetKind::kMesh, "torus");
  EXPECT_EQ(s.kind, ItemKind::kBuiltinShape);
  EXPECT_EQ(s.Key(), "shape:torus");
  EXPECT_EQ(s.name, "torus");
  EXPECT_TRUE(s.path.empty());
  const DatasetItem c = BuiltinItem(DatasetKind::kCurves, "star");
  EXPECT_EQ(c.kind, ItemKind::kBuiltinCurve);
  EXPECT_EQ(c.Key(), "curve:star");
  EXPECT_EQ(c.Dataset(), DatasetKind::kCurves);
  EXPECT_EQ(c.Describe(), "built-in curve 'star'");
}

TEST(ItemsTest, UnknownBuiltinsNameTheValidOnesAndTheNearest) {
  const std::string shape = ErrorOf(DatasetKind::kMesh, "tours");
  EXPECT_NE(shape.find("unknown built-in shape 'tours' (did you mean 'torus'?)"), std::string::npos) << shape;
  EXPECT_NE(shape.find("valid: sphere, torus, knot, two_tori"), std::string::npos) << shape;
  const std::string curve = ErrorOf(DatasetKind::kCurves, "torus");  // a shape is not a curve
  EXPECT_NE(curve.find("unknown built-in curve 'torus'"), std::string::npos) << curve;
  EXPECT_NE(curve.find("circle"), std::string::npos) << curve;
  EXPECT_NE(ErrorOf(DatasetKind::kPoints, "sphere").find("a 'kind: points' dataset needs 'files'"), std::string::npos);
}

TEST(ItemsTest, DatasetKindNamesRoundTrip) {
  for (DatasetKind k : {DatasetKind::kMesh, DatasetKind::kPoints, DatasetKind::kCurves}) {
    DatasetKind back = DatasetKind::kMesh;
    ASSERT_TRUE(ParseDatasetKind(DatasetKindName(k), &back));
    EXPECT_EQ(back, k);
  }
  DatasetKind k;
  EXPECT_FALSE(ParseDatasetKind("meshes", &k));
}

}  // namespace
}  // namespace arcs
