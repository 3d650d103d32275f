// arcs voxelize MESH OUT.npy: winding-number occupancy grid of a mesh.
#include "app/cli.h"
#include "app/mesh_input.h"
#include "app/commands.h"
#include "framework/error.h"
#include "framework/geometry/normalize.h"
#include "framework/io/mesh_io.h"
#include "framework/io/npy.h"
#include "framework/io/sdf_io.h"
#include "framework/util/parallel.h"
#include "framework/voxel/voxelize.h"
#include "stages/voxel/voxel_params.h"

#include <cctype>
#include <chrono>
#include <filesystem>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace arcs {

namespace {

const char* kVoxelizeHelpHead = R"(usage: arcs voxelize MESH OUT [options]

Winding-number occupancy (Luo et al., Alg. 1) of MESH on an r x r x r grid.
OUT.npy is an (r, r, r) array with arr[i, j, k] the value at (x_i, y_j, z_k),
x_i = linspace(lo_x, hi_x, r)[i] (the layout of `arcs sdf` grids; numpy
meshgrid indexing='ij'), plus the sidecar OUT.npy.bounds
("xmin ymin zmin xmax ymax zmax") that the SDF .npy reader uses. OUT.npz holds
S (that array), bounds (2, 3) and U (the nodes); OUT.txt (.xyzs, .sdf) holds
one line "x y z value" per node.

The voxelize stage's parameters (`arcs describe voxelize`):
)";

const char* kVoxelizeHelpTail = R"(
  --normalize           centre the mesh, longest side 2, i.e. into [-1, 1]
                        (default), grid over [-1, 1]^3
  --no-normalize        keep coordinates; grid over the bounding box grown by
                        5 % per side unless --lo / --hi are given
  --lo V | --lo X,Y,Z   grid lower corner   --hi V | --hi X,Y,Z  upper corner
  --dtype float32|float64   array type (default float32)
  --threads T           worker threads (default: all cores)
  --verify              check the occupancy against the exact sum: hierarchy at
                        every node, exact sum where the two disagree or
                        ||w| - 1/2| < 0.1, and at N random nodes; exits 1
                        on any sign difference
  --verify-random N     random nodes of --verify (default 10 000)
)";

Vec3 ParseCorner(const std::string& s, const std::string& what) {
  std::vector<double> v;
  std::stringstream ss(s);
  std::string tok;
  while (std::getline(ss, tok, ',')) v.push_back(cli::ParseDouble(tok, what));
  if (v.size() == 1) return Vec3::Constant(v[0]);
  if (v.size() == 3) return Vec3(v[0], v[1], v[2]);
  cli::Usage(what + " takes one number or X,Y,Z, got '" + s + "'");
}

// OUT by extension: .npy (the array + bounds sidecar), .npz (S = the array,
// bounds, U = the nodes: what the SDF readers take) or text (.txt .xyzs .sdf:
// "x y z value" per node); anything else is refused before any work.
void CheckVolumeExtension(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  for (auto& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (e != ".npy" && e != ".npz" && e != ".txt" && e != ".xyzs" && e != ".sdf")
    throw InputError(path, 0, "unsupported volume output extension '" + e +
                                  "' (supported: .npy (array + .bounds sidecar), .npz (S, bounds, U), "
                                  ".txt .xyzs .sdf (text 'x y z value'))");
}

void WriteVolume(const std::string& path, const VolumeGrid& vol, bool f32) {
  const GridInfo& g = vol.info;
  if (std::filesystem::path(path).extension() != ".npy") {
    NpyArray arr;  // numpy C order
    arr.shape = {g.dims[0], g.dims[1], g.dims[2]};
    arr.data.resize(static_cast<std::size_t>(g.NumNodes()));
    for (int i = 0; i < g.dims[0]; ++i)
      for (int j = 0; j < g.dims[1]; ++j)
        for (int k = 0; k < g.dims[2]; ++k)
          arr.data[(static_cast<std::size_t>(i) * g.dims[1] + j) * g.dims[2] + k] =
              vol.values[i + static_cast<std::int64_t>(g.dims[0]) * (j + static_cast<std::int64_t>(g.dims[1]) * k)];
    WriteSdf(path, SdfGridFromArray(path, arr, g.min, g.max));
    return;
  }
  const int nx = g.dims[0], ny = g.dims[1], nz = g.dims[2];
  const std::vector<std::int64_t> shape = {nx, ny, nz};
  std::vector<double> d(static_cast<std::size_t>(g.NumNodes()));
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j)
      for (int k = 0; k < nz; ++k)
        d[(static_cast<std::size_t>(i) * ny + j) * nz + k] =
            vol.values[i + static_cast<std::int64_t>(nx) * (j + static_cast<std::int64_t>(ny) * k)];
  if (f32) {
    std::vector<float> f(d.begin(), d.end());
    WriteNpy(path, f.data(), shape);
  } else {
    WriteNpy(path, d.data(), shape);
  }
  std::ofstream b(SdfBoundsPath(path));
  char buf[256];
  std::snprintf(buf, sizeof buf, "# arcs grid bounds: xmin ymin zmin xmax ymax zmax\n%.17g %.17g %.17g %.17g %.17g %.17g\n",
                g.min[0], g.min[1], g.min[2], g.max[0], g.max[1], g.max[2]);
  b << buf;
  if (!b) throw Error("cannot write '" + SdfBoundsPath(path) + "'");
}

// The stage's flags: every parameter of the voxelize stage but the grid box,
// whose corners this command takes as --lo / --hi (one number or X,Y,Z) and
// defaults from --normalize.
std::vector<cli::SchemaFlag> VoxelizeFlags(const Registry& registry) {
  return cli::StageFlags(registry, "voxelize", {"lo", "hi"});
}

}  // namespace

int CmdVoxelize(Registry& registry, int argc, char** argv) {
  const std::vector<cli::SchemaFlag> flags = VoxelizeFlags(registry);
  for (int i = 2; i < argc; ++i)
    if (std::string(argv[i]) == "--help" || std::string(argv[i]) == "-h") {
      std::fputs(kVoxelizeHelpHead, stdout);
      std::fputs(cli::FlagHelp(flags).c_str(), stdout);
      std::fputs(kVoxelizeHelpTail, stdout);
      return 0;
    }
  std::vector<std::string> with_value = cli::FlagNames(flags);
  for (const char* f : {"--lo", "--hi", "--dtype", "--threads", "--verify-random"}) with_value.push_back(f);
  const cli::Args a = cli::Parse(argc, argv, 2, with_value, {"--normalize", "--no-normalize", "--verify"});
  if (a.positional.size() != 2) cli::Usage("voxelize needs MESH and OUT.npy (run `arcs voxelize --help`)");
  const std::string in = a.positional[0], out = a.positional[1];
  CheckVolumeExtension(out);
  const VoxelizeStageOptions so = VoxelizeParams().Decode(cli::ResolveStageFlags(registry, "voxelize", flags, a));
  const VoxelizeOptions& o = so.voxelize;
  const int res = so.resolution;
  const std::string dtype = a.Get("--dtype", "float32");
  if (dtype != "float32" && dtype != "float64") cli::Usage("--dtype must be float32 or float64, got '" + dtype + "'");
  if (a.Has("--normalize") && a.Has("--no-normalize")) cli::Usage("--normalize and --no-normalize exclude each other");
  const bool normalize = !a.Has("--no-normalize");
  std::unique_ptr<ThreadLimit> limit;
  if (a.Has("--threads")) {
    const int t = cli::ParseInt(a.Get("--threads"), "--threads", 1, 4096);
    if (t < 1) cli::Usage("--threads must be >= 1");
    limit = std::make_unique<ThreadLimit>(t);
  }

  Mesh mesh = cli::ReadMeshForCommand(in);
  Vec3 lo, hi;
  if (normalize) {
    NormalizeOptions no;
    no.center = true;
    no.longest_side = 2.0;
    cli::NormalizeForCommand(&mesh, no, in);
    lo = Vec3::Constant(-1.0), hi = Vec3::Constant(1.0);
  } else {
    cli::CheckCoordinateRange(mesh, in);
    const Vec3 mn = mesh.V.colwise().minCoeff().transpose(), mx = mesh.V.colwise().maxCoeff().transpose();
    const double pad = std::max(0.05 * (mx - mn).maxCoeff(), 1e-9);
    lo = mn - Vec3::Constant(pad), hi = mx + Vec3::Constant(pad);
  }
  if (a.Has("--lo")) lo = ParseCorner(a.Get("--lo"), "--lo");
  if (a.Has("--hi")) hi = ParseCorner(a.Get("--hi"), "--hi");
  GridInfo g;
  try {
    g = CubeGrid(res, lo, hi);
  } catch (const OptionError& e) {
    cli::Usage(std::string("voxelize: ") + e.what());
  }
  VoxelizeReport rep;
  const auto t0 = std::chrono::steady_clock::now();
  const VolumeGrid vol = Voxelize(mesh, g, o, &rep);
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  WriteVolume(out, vol, dtype == "float32");
  std::printf("voxelize: %s -> %s (%d^3, method %s, path %s): %lld occupied nodes, %lld unbalanced edges, "
              "%lld degenerate faces dropped, %lld components, %lld exact evaluations, %lld sheet faces, %.3f s\n",
              in.c_str(), out.c_str(), res, o.method.c_str(), rep.path.c_str(), static_cast<long long>(rep.occupied),
              static_cast<long long>(rep.unbalanced_edges), static_cast<long long>(rep.dropped_faces),
              static_cast<long long>(rep.components), static_cast<long long>(rep.exact_evaluations),
              static_cast<long long>(rep.sheet_faces), secs);
  if (a.Has("--verify")) {
    VolumeGrid occ = vol;
    if (o.output == "winding")
      for (std::int64_t p = 0; p < occ.values.size(); ++p) occ.values[p] = occ.values[p] > 0.5 ? 1.0 : 0.0;
    if (rep.sheet_faces > 0 || o.open_mesh == "flip_dup")
      std::printf("verify: note: the open-mesh rule changed the occupancy (shell / Alg. 2); differences are expected\n");
    const int nr = a.Has("--verify-random") ? cli::ParseInt(a.Get("--verify-random"), "--verify-random", 0, 1000000000) : 10000;
    if (nr < 0) cli::Usage("--verify-random must be >= 0");
    const SignCheck sc = VerifyOccupancy(mesh, occ, o.orientation, 0.1, nr, 1);
    std::printf("verify: %lld nodes, %lld disagree with the hierarchy, %lld checked with the exact sum, "
                "%lld sign differences from the exact sum\n",
                static_cast<long long>(sc.nodes), static_cast<long long>(sc.fast_disagreements),
                static_cast<long long>(sc.exact_checked), static_cast<long long>(sc.differences));
    if (sc.differences > 0) return 1;
  }
  return 0;
}

}  // namespace arcs
