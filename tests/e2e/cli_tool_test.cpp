// The command line as a researcher uses it (issue 14): --help on every
// subcommand, global options anywhere, --version, point clouds through
// `arcs reconstruct`, formats by extension (.npy .npz text) round-tripping,
// `arcs eval` in one frame with --json, outputs in the input's frame.
#include "orchestration/csv.h"
#include "framework/geometry/builtin_shapes.h"
#include "framework/geometry/transform_file.h"
#include "framework/io/mesh_io.h"
#include "framework/io/npy.h"
#include "framework/io/sdf_io.h"
#include "tests/e2e/e2e_util.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>

namespace arcs::testing {
namespace {

double JsonNumber(const std::string& json, const std::string& key) {
  const size_t k = json.find("\"" + key + "\": ");
  if (k == std::string::npos) return NAN;
  return std::strtod(json.c_str() + k + key.size() + 4, nullptr);
}

TEST(CliTool, EveryCommandHasHelp) {
  for (const char* c : {"run", "table", "list", "describe", "sdf", "eval", "reconstruct", "shape", "voxelize",
                        "morph", "version"}) {
    for (const char* flag : {"--help", "-h"}) {
      const CmdResult r = RunCmd(Arcs() + " " + c + " " + flag);
      EXPECT_EQ(r.code, 0) << c << " " << flag << "\n" << r.output;
      EXPECT_NE(r.output.find("usage"), std::string::npos) << c;
      EXPECT_NE(r.output.find("--"), std::string::npos) << c << ": lists no option";
    }
  }
  // Generated from the schema: the method's parameters with defaults.
  const CmdResult r = RunCmd(Arcs() + " reconstruct --method graph_voronoi --help");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("graph_voronoi (reconstructor)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("--param "), std::string::npos) << r.output;
  const CmdResult rfta = RunCmd(Arcs() + " reconstruct --help");
  EXPECT_NE(rfta.output.find("--param iterations=V"), std::string::npos) << rfta.output;
  EXPECT_NE(rfta.output.find("screened_poisson"), std::string::npos);
}

TEST(CliTool, VersionAndGlobalOptionsAnywhere) {
  const CmdResult v = RunCmd(Arcs() + " --version");
  EXPECT_EQ(v.code, 0);
  EXPECT_EQ(v.output.rfind("arcs 0.1.0", 0), 0u) << v.output;
  // The revision is the build's stamp (the code compiled, "-dirty" when
  // tracked files differed), not the one cmake saw when it configured.
  if (RunCmd(std::string("git -C '") + ARCS_SOURCE_DIR + "' rev-parse --short=12 HEAD").code == 0) {
    std::string bin = Arcs();  // quoted for the shell
    bin.erase(std::remove(bin.begin(), bin.end(), '\''), bin.end());
    const std::filesystem::path stamp =
        std::filesystem::path(bin).parent_path().parent_path() / "arcs_revision_stamp.cpp";
    ASSERT_TRUE(std::filesystem::exists(stamp)) << stamp;
    std::ifstream in(stamp);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::size_t q0 = text.find("SetGitRevision(\""), q1 = text.find('"', q0 + 16);
    ASSERT_NE(q0, std::string::npos) << text;
    const std::string rev = text.substr(q0 + 16, q1 - q0 - 16);
    ASSERT_GE(rev.size(), 12u) << rev;
    EXPECT_NE(v.output.find("(git " + rev + ","), std::string::npos) << v.output << " vs stamp " << rev;
  }
  const CmdResult p = RunCmd(Arcs() + " --plugin '" + ARCS_EXAMPLE_PLUGIN + "' --threads 1 list");
  ASSERT_EQ(p.code, 0) << p.output;
  EXPECT_NE(p.output.find(ARCS_EXAMPLE_PLUGIN), std::string::npos) << p.output;  // the plugin's stage, with its origin
  const CmdResult t = RunCmd(Arcs() + " --threads 1 shape list");
  EXPECT_EQ(t.code, 0) << t.output;
  const CmdResult bad = RunCmd(Arcs() + " --threads x list");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.output.find("--threads must be an integer"), std::string::npos) << bad.output;
}

// Oriented samples of a sphere of radius r centred at c, as an .xyz file.
std::string SphereXyz(const std::filesystem::path& dir, double r, const Vec3& c, int n, bool normals) {
  std::mt19937 rng(1);
  std::normal_distribution<double> g;
  std::string text;
  char buf[200];
  for (int i = 0; i < n; ++i) {
    Vec3 d(g(rng), g(rng), g(rng));
    d.normalize();
    const Vec3 p = c + r * d;
    if (normals)
      std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g %.17g %.17g %.17g\n", p.x(), p.y(), p.z(), d.x(), d.y(), d.z());
    else
      std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g\n", p.x(), p.y(), p.z());
    text += buf;
  }
  const auto path = dir / (normals ? "sphere_n.xyz" : "sphere.xyz");
  WriteFile(path, text);
  return path.string();
}

double MeanDistanceTo(const Mesh& m, const Vec3& c) {
  double s = 0;
  for (int i = 0; i < m.NumVertices(); ++i) s += (m.V.row(i).transpose() - c).norm();
  return s / m.NumVertices();
}

TEST(CliTool, ReconstructPointCloudsInTheInputFrame) {
  const auto dir = TempDir("cli_points");
  const Vec3 c(10, -3, 2);
  const std::string with_n = SphereXyz(dir, 4.0, c, 3000, true), without = SphereXyz(dir, 4.0, c, 3000, false);
  const std::string out = (dir / "sp.ply").string();
  CmdResult r = RunCmd(Arcs() + " reconstruct '" + with_n + "' '" + out + "' --method screened_poisson");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NEAR(MeanDistanceTo(ReadMesh(out), c), 4.0, 0.05 * 4.0);
  // Without normals, estimate_normals runs first; graph_voronoi needs none.
  r = RunCmd(Arcs() + " reconstruct '" + without + "' '" + out + "' --method screened_poisson");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("normals estimated"), std::string::npos) << r.output;
  EXPECT_NEAR(MeanDistanceTo(ReadMesh(out), c), 4.0, 0.05 * 4.0);
  const std::string gv = (dir / "gv.obj").string();
  r = RunCmd(Arcs() + " reconstruct '" + without + "' '" + gv + "' --method graph_voronoi");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NEAR(MeanDistanceTo(ReadMesh(gv), c), 4.0, 0.05 * 4.0);
  // --frame normalized: the unit frame, the transform recorded beside.
  const std::string nf = (dir / "nf.ply").string();
  r = RunCmd(Arcs() + " reconstruct '" + with_n + "' '" + nf + "' --frame normalized --param depth=6");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NEAR(MeanDistanceTo(ReadMesh(nf), Vec3::Zero()), 0.5, 0.05 * 0.5);
  const std::string sidecar = ReadFile(nf + ".transform.json");
  EXPECT_NE(sidecar.find("\"scale\": 0.125"), std::string::npos) << sidecar;
  // (N, 6) .npy points.
  std::vector<double> rows;
  std::mt19937 rng(2);
  std::normal_distribution<double> g;
  for (int i = 0; i < 2000; ++i) {
    Vec3 d(g(rng), g(rng), g(rng));
    d.normalize();
    for (int k = 0; k < 3; ++k) rows.push_back(0.3 * d[k]);
    for (int k = 0; k < 3; ++k) rows.push_back(d[k]);
  }
  WriteNpy((dir / "p.npy").string(), rows.data(), {2000, 6});
  r = RunCmd(Arcs() + " reconstruct '" + (dir / "p.npy").string() + "' '" + out + "' --method ball_pivoting");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NEAR(MeanDistanceTo(ReadMesh(out), Vec3::Zero()), 0.3, 0.03);
  // Clear errors: output format, parameter, method role.
  r = RunCmd(Arcs() + " reconstruct '" + with_n + "' '" + (dir / "x.npy").string() + "' --method screened_poisson");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.output.find("unsupported mesh output extension '.npy'"), std::string::npos) << r.output;
  r = RunCmd(Arcs() + " reconstruct '" + with_n + "' '" + out + "' --method graph_voronoi --param dept=3");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("stage 'graph_voronoi' has no parameter 'dept'"), std::string::npos) << r.output;
}

TEST(CliTool, EvalInOneFrameAndJson) {
  const auto dir = TempDir("cli_eval");
  Mesh knot = MakeBuiltinShape("knot");
  knot.V = (knot.V * 7.0).rowwise() + Eigen::RowVector3d(1, 2, 3);
  const std::string k = (dir / "k.ply").string();
  WriteMesh(k, knot);
  const CmdResult r = RunCmd(Arcs() + " eval '" + k + "' '" + k + "' --samples 100000 --json");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_LT(JsonNumber(r.output, "chamfer"), 0.01) << r.output;
  EXPECT_LT(JsonNumber(r.output, "hausdorff"), 1e-9) << r.output;
  EXPECT_NE(r.output.find("\"frame\": \"reference\""), std::string::npos);
  // each: scale and placement ignored; none: as stored (the raw Chamfer is 7x the unit one).
  Mesh unit = MakeBuiltinShape("knot");
  const std::string u = (dir / "u.obj").string();
  WriteMesh(u, unit);
  const CmdResult each = RunCmd(Arcs() + " eval '" + u + "' '" + k + "' --samples 20000 --json --frame each");
  EXPECT_LT(JsonNumber(each.output, "chamfer"), 0.02) << each.output;
  const CmdResult ref = RunCmd(Arcs() + " eval '" + u + "' '" + k + "' --samples 20000 --json");
  EXPECT_GT(JsonNumber(ref.output, "chamfer"), 0.1) << ref.output;
  const CmdResult bad = RunCmd(Arcs() + " eval '" + u + "' '" + k + "' --frame mine");
  EXPECT_EQ(bad.code, 2);
}

// A stage-valued --param in the form --help prints its default in:
// STAGE(name=value, ...). Named like the default, it starts from the
// default's parameters (rfta's official screened-Poisson call), as a nested
// stage in an experiment file does; screened_poisson's own defaults (PCL,
// automatic depth) would give another mesh.
TEST(CliTool, ReconstructNestedStageParameters) {
  const auto dir = TempDir("cli_nested");
  const std::string in = (dir / "t.npz").string();
  const CmdResult s = RunCmd(Arcs() + " sdf shape:torus '" + in + "' --n 10");
  ASSERT_EQ(s.code, 0) << s.output;
  const auto bytes = [](const std::filesystem::path& p) {
    std::ifstream f(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
  };
  const auto run = [&](const std::string& name, const std::string& params) {
    const CmdResult r = RunCmd(Arcs() + " reconstruct '" + in + "' '" + (dir / name).string() + "' --threads 1 " + params);
    EXPECT_EQ(r.code, 0) << params << "\n" << r.output;
    return bytes(dir / name);
  };
  const std::string plain = run("plain.ply", "");
  ASSERT_FALSE(plain.empty());
  // The default final surface's weight (15: the official call in full, session 39) given explicitly.
  EXPECT_EQ(run("same.ply", "--param 'reconstructor=screened_poisson(point_weight=15)' "
                            "--param 'tuning_reconstructor=screened_poisson'"),
            plain);
  EXPECT_NE(run("heavier.ply", "--param 'reconstructor=screened_poisson(point_weight=40, normal_splat=ceil)'"), plain);
  for (const auto& [param, message] : std::vector<std::pair<std::string, std::string>>{
           {"reconstructor=screened_poisson(normal_splt=ceil)", "stage 'screened_poisson' has no parameter 'normal_splt'"},
           {"reconstructor=screened_poisson(point_weight=15", "expected STAGE(name=value, ...)"},
           {"reconstructor=screened_poisson(point_weight=heavy)", "screened_poisson.point_weight must be a number"},
           {"reconstructor=screened_poison", "did you mean 'screened_poisson'"}}) {
    const CmdResult r = RunCmd(Arcs() + " reconstruct '" + in + "' '" + (dir / "x.ply").string() + "' --param '" + param + "'");
    EXPECT_EQ(r.code, 2) << param << "\n" << r.output;
    EXPECT_NE(r.output.find(message), std::string::npos) << r.output;
  }
}

TEST(CliTool, SdfReconstructVoxelizeRoundTripEveryFormat) {
  const auto dir = TempDir("cli_formats");
  // Grid: .npy, .npz and text hold the same samples; MC on the grids agrees.
  std::vector<SdfSamples> grids;
  for (const char* ext : {".npy", ".npz", ".txt"}) {
    const std::string p = (dir / (std::string("g") + ext)).string();
    const CmdResult s = RunCmd(Arcs() + " sdf shape:torus '" + p + "' --n 12");
    ASSERT_EQ(s.code, 0) << s.output;
    EXPECT_TRUE(std::filesystem::exists(p + ".transform.json"));
    grids.push_back(ReadSdf(p));
  }
  EXPECT_EQ(grids[0].values, grids[1].values);
  EXPECT_EQ(grids[0].points, grids[1].points);
  EXPECT_EQ(grids[0].values, grids[2].values);  // text: exact decimals
  EXPECT_TRUE(grids[1].grid);
  for (const char* ext : {".npy", ".npz"}) {
    const std::string in = (dir / (std::string("g") + ext)).string(), out = (dir / (std::string("mc") + ext + ".ply")).string();
    const CmdResult r = RunCmd(Arcs() + " reconstruct '" + in + "' '" + out + "' --method marching_cubes");
    ASSERT_EQ(r.code, 0) << r.output;
  }
  const Mesh a = ReadMesh((dir / "mc.npy.ply").string()), b = ReadMesh((dir / "mc.npz.ply").string());
  EXPECT_EQ(a.V, b.V);
  // The sidecar maps the mesh back into the shape's own frame (the torus as `arcs shape` writes it).
  const Mesh torus = MakeBuiltinShape("torus");
  EXPECT_NEAR(a.V.col(0).maxCoeff(), torus.V.col(0).maxCoeff(), 0.05 * torus.V.col(0).maxCoeff());
  // Random samples: (N, 4) .npy, .npz, text.
  for (const char* ext : {".npy", ".npz", ".txt"}) {
    const std::string p = (dir / (std::string("r") + ext)).string();
    const CmdResult s = RunCmd(Arcs() + " sdf shape:sphere '" + p + "' --random 500");
    ASSERT_EQ(s.code, 0) << s.output;
    const SdfSamples r = ReadSdf(p);
    EXPECT_EQ(r.Size(), 500);
    EXPECT_FALSE(r.grid);
  }
  EXPECT_EQ(ReadSdf((dir / "r.npy").string()).values, ReadSdf((dir / "r.npz").string()).values);
  EXPECT_EQ(ReadSdf((dir / "r.npy").string()).values, ReadSdf((dir / "r.txt").string()).values);
  const CmdResult wrong = RunCmd(Arcs() + " sdf shape:sphere '" + (dir / "r.xyz").string() + "' --random 10");
  EXPECT_EQ(wrong.code, 1);
  EXPECT_NE(wrong.output.find("unsupported SDF output extension '.xyz'"), std::string::npos) << wrong.output;
  // Voxelize: .npy, .npz, text hold the same occupancy.
  const std::string mesh = (dir / "t.obj").string();
  ASSERT_EQ(RunCmd(Arcs() + " shape torus '" + mesh + "'").code, 0);
  std::vector<SdfSamples> vox;
  for (const char* ext : {".npy", ".npz", ".txt"}) {
    const std::string p = (dir / (std::string("v") + ext)).string();
    const CmdResult s = RunCmd(Arcs() + " voxelize '" + mesh + "' '" + p + "' --resolution 16");
    ASSERT_EQ(s.code, 0) << s.output;
    vox.push_back(ReadSdf(p));
  }
  EXPECT_EQ(vox[0].values, vox[1].values);
  EXPECT_EQ(vox[0].values, vox[2].values);
  EXPECT_GT(vox[0].values.sum(), 10);
  const CmdResult vbad = RunCmd(Arcs() + " voxelize '" + mesh + "' '" + (dir / "v.png").string() + "'");
  EXPECT_EQ(vbad.code, 1);
  EXPECT_NE(vbad.output.find("unsupported volume output extension '.png'"), std::string::npos) << vbad.output;
}

TEST(CliTool, SavedOutputsRecordTheirFrame) {
  const auto dir = TempDir("cli_saved_frame");
  Mesh sphere = MakeBuiltinShape("sphere");
  sphere.V = (sphere.V * 4.0).rowwise() + Eigen::RowVector3d(5, 0, 0);  // radius 2 at (5, 0, 0)
  WriteMesh((dir / "big.obj").string(), sphere);
  WriteFile(dir / "e.yaml",
            "name: frame\ndatasets: [{name: d, files: [big.obj]}]\n"
            "inputs:\n  - name: grid\n    pipeline:\n      - stage: sdf_grid\n        params: {n: 12}\n"
            "methods:\n  - name: MC\n    pipeline: [marching_cubes]\nmetrics: [mesh_size]\n");
  const CmdResult r = RunCmd(Arcs() + " run '" + (dir / "e.yaml").string() + "' --save-outputs --out '" +
                             (dir / "out").string() + "'");
  ASSERT_EQ(r.code, 0) << r.output;
  const CsvTable t = ReadCsv((dir / "out" / "results.csv").string());
  const std::string out = (dir / "out" / "outputs" / t.Cell(0, "output_file")).string();
  Similarity s;
  ASSERT_TRUE(ReadTransformSidecar(out, &s));
  EXPECT_NEAR(s.scale, 0.25, 0.01);  // longest side 4 -> 1
  // The recorded transform takes the saved (normalised) mesh back onto the dataset file's sphere.
  const Mesh back = ApplyInverseSimilarity(s, ReadMesh(out));
  EXPECT_NEAR(MeanDistanceTo(back, Vec3(5, 0, 0)), 2.0, 0.05 * 2.0);
}

TEST(CliTool, ScansFromSharedData) {
  ARCS_REQUIRE_SHARED_DATA();
  const auto dir = TempDir("cli_scans");
  const std::string scan = SharedData("scans/cgal_points/kitten.xyz");
  for (const char* method : {"screened_poisson", "graph_voronoi"}) {
    const std::string out = (dir / (std::string(method) + ".ply")).string();
    const CmdResult r = RunCmd(Arcs() + " reconstruct '" + scan + "' '" + out + "' --method " + method);
    ASSERT_EQ(r.code, 0) << r.output;
    const Mesh m = ReadMesh(out);
    EXPECT_GT(m.NumFaces(), 100) << method;
    const CmdResult e = RunCmd(Arcs() + " eval '" + out + "' '" + out + "' --json --samples 200000");
    ASSERT_EQ(e.code, 0) << e.output;
    EXPECT_LT(JsonNumber(e.output, "chamfer"), 0.01) << e.output;
  }
}

}  // namespace
}  // namespace arcs::testing
