// `save_outputs` / `arcs run --save-outputs`: each case's output mesh, 2D
// curve and the method's oriented points are written under <out>/outputs/,
// named after the case, and are the very outputs the metrics measured.
#include "framework/geometry/curves.h"
#include "framework/io/mesh_io.h"
#include "framework/io/points_io.h"
#include "tests/e2e/e2e_util.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

namespace arcs {
namespace {

namespace fs = std::filesystem;
using testing::Arcs;
using testing::RunCmd;

TEST(SaveOutputsTest, MeshesAndTangencyPointsAreWrittenPerCase) {
  const auto dir = testing::TempDir("save_outputs_3d");
  testing::WriteFile(dir / "e.yaml",
                     "name: save3d\nsave_outputs: true\n"
                     "datasets: [{shapes: [sphere]}]\n"
                     "inputs:\n  - name: grid\n    pipeline:\n      - stage: sdf_grid\n        params: {n: [8, 12]}\n"
                     "methods:\n  - name: MC\n    pipeline: [marching_cubes]\n"
                     "  - name: RFTA\n    pipeline:\n      - stage: rfta\n        params: {iterations: 1}\n"
                     "metrics: [mesh_size]\n");
  const auto r = RunCmd(Arcs() + " run " + (dir / "e.yaml").string() + " --out " + (dir / "out").string());
  ASSERT_EQ(r.code, 0) << r.output;
  const CsvTable t = ReadCsv((dir / "out" / "results.csv").string());
  ASSERT_EQ(t.rows.size(), 4u);
  for (size_t i = 0; i < t.rows.size(); ++i) {
    ASSERT_EQ(t.Cell(i, "status"), "ok") << t.Cell(i, "error");
    const std::string file = t.Cell(i, "output_file");
    // Named item_<varying params>__input__method__id.ply.
    EXPECT_EQ(file, "sphere_n=" + t.Cell(i, "sdf_grid.n") + "__grid__" + t.Cell(i, "method") + "__" +
                        t.Cell(i, "case_id") + ".ply");
    const Mesh m = ReadMesh((dir / "out" / "outputs" / file).string());
    EXPECT_EQ(m.NumVertices(), std::stoi(t.Cell(i, "out_vertices")));
    EXPECT_EQ(m.NumFaces(), std::stoi(t.Cell(i, "out_faces")));
    // On the unit-normalised sphere (radius 0.5 after longest side 1).
    for (int v = 0; v < m.NumVertices(); v += 7) EXPECT_NEAR(m.V.row(v).norm(), 0.5, 0.1);
    const std::string pts = t.Cell(i, "output_points_file");
    if (t.Cell(i, "method") == "RFTA") {
      ASSERT_FALSE(pts.empty());
      const PointCloud pc = ReadPointCloud((dir / "out" / "outputs" / pts).string());
      EXPECT_EQ(pc.Size(), std::stoi(t.Cell(i, "rfta_points")));
      EXPECT_TRUE(pc.HasNormals());
    } else {
      EXPECT_TRUE(pts.empty()) << pts;
    }
  }
  // Nothing half-written is left behind.
  for (const auto& e : fs::directory_iterator(dir / "out" / "outputs"))
    EXPECT_EQ(e.path().string().find(".part"), std::string::npos) << e.path();
}

// Several varying nested stage parameters make the case label longer than a
// file name may be (255 bytes): it was "File name too long"; the stem is now
// capped (first 120 label characters, a hash, the case id). Labels name only
// the nested parameters that vary (not the whole resolved call), so it takes
// several varying ones to reach the cap.
TEST(SaveOutputsTest, LongLabelsGiveCappedUniqueFileNames) {
  const auto dir = testing::TempDir("save_outputs_long");
  std::string recs;
  for (const char* p : {"depth: 6, min_depth: 4, point_weight: 1, samples_per_node: 1.5, scale: 1.25",
                        "depth: 5, min_depth: 3, point_weight: 4, samples_per_node: 2, scale: 1.3"}) {
    recs += std::string("            - {stage: screened_poisson, params: {") + p +
            ", open_retries: 0, manifold: true, threads: 1}}\n";
  }
  testing::WriteFile(dir / "e.yaml",
                     "name: savelong\nsave_outputs: true\n"
                     "datasets: [{shapes: [sphere]}]\n"
                     "inputs:\n  - name: grid\n    pipeline:\n      - stage: sdf_grid\n        params: {n: 8}\n"
                     "methods:\n  - name: RFTA\n    pipeline:\n      - stage: rfta\n        params:\n"
                     "          iterations: 1\n          reconstructor:\n" + recs +
                     "          tuning_reconstructor:\n" + recs + "metrics: [mesh_size]\n");
  const auto r = RunCmd(Arcs() + " run " + (dir / "e.yaml").string() + " --out " + (dir / "out").string());
  ASSERT_EQ(r.code, 0) << r.output;
  const CsvTable t = ReadCsv((dir / "out" / "results.csv").string());
  ASSERT_EQ(t.rows.size(), 4u);
  std::set<std::string> names;
  for (size_t i = 0; i < t.rows.size(); ++i) {
    ASSERT_EQ(t.Cell(i, "status"), "ok") << t.Cell(i, "error");
    for (const char* col : {"output_file", "output_points_file"}) {
      const std::string file = t.Cell(i, col);
      ASSERT_FALSE(file.empty()) << col;
      EXPECT_LE(file.size(), 200u) << file;
      EXPECT_TRUE(fs::exists(dir / "out" / "outputs" / file)) << file;
      EXPECT_NE(file.find("__" + t.Cell(i, "case_id")), std::string::npos) << file;
      EXPECT_EQ(file.rfind("sphere_reconstructor=", 0), 0u) << file;  // still starts with the label
      EXPECT_NE(file.find('~'), std::string::npos) << file;  // capped, with the hash
      EXPECT_NE(file.find("point_weight="), std::string::npos) << file;  // what varies
      EXPECT_EQ(file.find("threads="), std::string::npos) << file;       // what does not
      names.insert(file);
    }
  }
  EXPECT_EQ(names.size(), 8u);  // unique per case and kind
}

TEST(SaveOutputsTest, CommandLineFlagAndCurvesAndOffByDefault) {
  const auto dir = testing::TempDir("save_outputs_2d");
  testing::WriteFile(dir / "e.yaml",
                     "name: save2d\n"
                     "datasets: [{kind: curves, shapes: [circle]}]\n"
                     "inputs:\n  - name: grid\n    pipeline:\n      - stage: sdf_grid_2d\n        params: {n: 16}\n"
                     "methods:\n  - name: MS\n    pipeline: [marching_squares]\n"
                     "metrics: [topology_2d]\n");
  // Off unless asked.
  auto r = RunCmd(Arcs() + " run " + (dir / "e.yaml").string() + " --out " + (dir / "off").string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_FALSE(fs::exists(dir / "off" / "outputs"));
  EXPECT_TRUE(ReadCsv((dir / "off" / "results.csv").string()).Cell(0, "output_file").empty());
  r = RunCmd(Arcs() + " run " + (dir / "e.yaml").string() + " --save-outputs --out " + (dir / "on").string());
  ASSERT_EQ(r.code, 0) << r.output;
  const CsvTable t = ReadCsv((dir / "on" / "results.csv").string());
  ASSERT_EQ(t.rows.size(), 1u);
  const std::string file = t.Cell(0, "output_file");
  EXPECT_EQ(file, "circle__grid__MS__" + t.Cell(0, "case_id") + ".obj");
  const Polyline c = ReadPolyline((dir / "on" / "outputs" / file).string());
  EXPECT_GT(c.NumEdges(), 20);
  for (int v = 0; v < c.NumVertices(); ++v) EXPECT_NEAR(c.V.row(v).norm(), 0.5, 0.05);
}

}  // namespace
}  // namespace arcs
