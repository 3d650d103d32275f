// Mutation fuzzing of every file reader (criterion: a clear arcs::Error or
// success, never a signal, a sanitizer finding or a timeout). Fixed seeds:
// the same mutants on every run; a failing mutant is kept in /tmp and named.
// ARCS_FUZZ_MUTANTS overrides the number of mutants per reader (default 300).
#include "framework/io/mesh_io.h"
#include "framework/io/npy.h"
#include "framework/io/points_io.h"
#include "framework/io/sdf_io.h"
#include "tests/fuzz_util.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace arcs {
namespace {

namespace fs = std::filesystem;

int Mutants() {
  if (const char* e = std::getenv("ARCS_FUZZ_MUTANTS")) return std::max(1, std::atoi(e));
  return 300;
}

Mesh Tetra() {
  Mesh m;
  m.V.resize(4, 3);
  m.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  m.F.resize(4, 3);
  m.F << 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3;
  return m;
}

std::string FileOf(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

// A seed written by our own writer (binary formats).
std::string Written(const std::string& ext, const std::function<void(const std::string&)>& write) {
  const fs::path p = fs::temp_directory_path() / ("arcs_fuzz_seed_" + std::to_string(getpid()) + ext);
  write(p.string());
  const std::string s = FileOf(p.string());
  fs::remove(p);
  return s;
}

void ReadAnyMesh(const std::string& p) {
  MeshReadReport rep;
  const Mesh m = ReadMesh(p, &rep);
  // The reader's promise: finite coordinates, indices in range.
  if (!m.V.allFinite()) throw std::logic_error("non-finite coordinate returned");
  for (int f = 0; f < m.NumFaces(); ++f)
    for (int k = 0; k < 3; ++k)
      if (m.F(f, k) < 0 || m.F(f, k) >= m.NumVertices()) throw std::logic_error("index out of range returned");
}

const char kObj[] =
    "\xEF\xBB\xBF# a tetrahedron\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1/3\nvn 0 0 1\n"
    "f 1 3 2\nf 1//1 2//1 4//1\nf -4 -1 -2\nf 2/1 3/1 4/1\n";
const char kOff[] = "OFF\n# c\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n4 1 2 3 1\n";
const char kPlyAscii[] =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
    "property float nx\nproperty float ny\nproperty float nz\n"
    "element face 4\nproperty list uchar int vertex_indices\nelement extra 2\nproperty list int double stuff\n"
    "end_header\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n0 0 1 0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"
    "2 1.5 2.5\n0\n";
const char kStlAscii[] =
    "solid t\nfacet normal 0 0 -1\nouter loop\nvertex 0 0 0\nvertex 0 1 0\nvertex 1 0 0\nendloop\nendfacet\n"
    "facet normal 0 -1 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 0 1\nendloop\nendfacet\n"
    "facet normal -1 0 0\nouter loop\nvertex 0 0 0\nvertex 0 0 1\nvertex 0 1 0\nendloop\nendfacet\n"
    "facet normal 1 1 1\nouter loop\nvertex 1 0 0\nvertex 0 1 0\nvertex 0 0 1\nendloop\nendfacet\nendsolid t\n";
const char kXyz[] = "# points\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n0.5 0.5 0.5 1 0 0\n";
const char kPcdAscii[] =
    "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z normal_x normal_y normal_z\nSIZE 4 4 4 4 4 4\nTYPE F F F F F F\n"
    "COUNT 1 1 1 1 1 1\nWIDTH 3\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA ascii\n"
    "0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n";
const char kSdfText[] = "# x y z s\n0 0 0 -0.5\n1 0 0 0.5\n0 1 0 0.5\n0 0 1 0.25\n0.5 0.5 0.5 0.1\n";

std::string PcdBinary() {
  std::string s =
      "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 8\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 3\nHEIGHT 1\nPOINTS 3\nDATA binary\n";
  for (int i = 0; i < 3; ++i) {
    const float a = static_cast<float>(i), b = 1.0f;
    const double c = 0.5 * i;
    s.append(reinterpret_cast<const char*>(&a), 4);
    s.append(reinterpret_cast<const char*>(&b), 4);
    s.append(reinterpret_cast<const char*>(&c), 8);
  }
  return s;
}

TEST(ReaderFuzz, Obj) { testing::FuzzReader("obj", kObj, ".obj", Mutants(), 101, ReadAnyMesh); }
TEST(ReaderFuzz, Off) { testing::FuzzReader("off", kOff, ".off", Mutants(), 102, ReadAnyMesh); }
TEST(ReaderFuzz, PlyAscii) { testing::FuzzReader("plya", kPlyAscii, ".ply", Mutants(), 103, ReadAnyMesh); }
TEST(ReaderFuzz, PlyBinary) {
  const std::string seed = Written(".ply", [](const std::string& p) { WriteMesh(p, Tetra()); });
  testing::FuzzReader("plyb", seed, ".ply", Mutants(), 104, ReadAnyMesh);
}
TEST(ReaderFuzz, StlAscii) { testing::FuzzReader("stla", kStlAscii, ".stl", Mutants(), 105, ReadAnyMesh); }
TEST(ReaderFuzz, StlBinary) {
  const std::string seed = Written(".stl", [](const std::string& p) { WriteMesh(p, Tetra()); });
  testing::FuzzReader("stlb", seed, ".stl", Mutants(), 106, ReadAnyMesh);
}
TEST(ReaderFuzz, PointsPly) {
  testing::FuzzReader("pply", kPlyAscii, ".ply", Mutants(), 107, [](const std::string& p) { ReadPointCloud(p); });
}
TEST(ReaderFuzz, Xyz) {
  testing::FuzzReader("xyz", kXyz, ".xyz", Mutants(), 108, [](const std::string& p) { ReadPointCloud(p); });
}
TEST(ReaderFuzz, PcdAscii) {
  testing::FuzzReader("pcda", kPcdAscii, ".pcd", Mutants(), 109, [](const std::string& p) { ReadPointCloud(p); });
}
TEST(ReaderFuzz, PcdBinary) {
  testing::FuzzReader("pcdb", PcdBinary(), ".pcd", Mutants(), 110, [](const std::string& p) { ReadPointCloud(p); });
}
TEST(ReaderFuzz, NpyGrid) {
  const std::string seed = Written(".npy", [](const std::string& p) {
    std::vector<double> v(3 * 4 * 5);
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = 0.1 * static_cast<double>(i) - 2.0;
    WriteNpy(p, v.data(), {3, 4, 5});
  });
  testing::FuzzReader("npyg", seed, ".npy", Mutants(), 111, [](const std::string& p) {
    ReadNpy(p);
    ReadSdf(p);
  });
}
TEST(ReaderFuzz, NpyScattered) {
  const std::string seed = Written(".npy", [](const std::string& p) {
    std::vector<float> v(6 * 4);
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = 0.25f * static_cast<float>(i % 7) - 0.5f;
    WriteNpy(p, v.data(), {6, 4});
  });
  testing::FuzzReader("npys", seed, ".npy", Mutants(), 112, [](const std::string& p) { ReadSdf(p); });
}
TEST(ReaderFuzz, SdfText) {
  testing::FuzzReader("sdft", kSdfText, ".txt", Mutants(), 113, [](const std::string& p) { ReadSdf(p); });
}

// The hostile headers of the issue, each refused at once with the file named.
TEST(ReaderFuzz, HugeCountsAreClearErrorsWithinASecond) {
  const fs::path dir = fs::temp_directory_path() / ("arcs_fuzz_huge_" + std::to_string(getpid()));
  fs::create_directories(dir);
  const std::vector<std::pair<std::string, std::string>> files = {
      {"empty_elem.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                         "element junk 1000000000000000000\nend_header\n0 0 0\n1 0 0\n0 1 0\n"},
      {"empty_elem_bin.ply", "ply\nformat binary_little_endian 1.0\nelement junk 1000000000000000000\n"
                             "element vertex 0\nproperty float x\nproperty float y\nproperty float z\nend_header\n"},
      {"huge_vertex.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000000000\n"
                          "property float x\nproperty float y\nproperty float z\nend_header\n\x01\x02\x03"},
      {"huge.off", "OFF\n1000000000000000000 1000000000000000000 0\n0 0 0\n"},
      {"huge.pcd", "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 1000000000000000000\n"
                   "HEIGHT 1\nPOINTS 1000000000000000000\nDATA binary\n0123456789ab"},
  };
  for (const auto& [name, bytes] : files) {
    const std::string p = (dir / name).string();
    std::ofstream(p, std::ios::binary) << bytes;
    const auto t0 = std::chrono::steady_clock::now();
    try {
      if (name.ends_with(".pcd")) {
        ReadPointCloud(p);
      } else {
        ReadMesh(p);
      }
      ADD_FAILURE() << name << ": no error";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 1.0) << name;
  }
  // An .npy header claiming 10^18 elements.
  std::string npy = "\x93NUMPY\x01";
  npy += '\0';
  std::string dict = "{'descr': '<f8', 'fortran_order': False, 'shape': (1000000000000000000, 3), }";
  dict.append(117 - dict.size(), ' ');
  dict += '\n';
  npy += static_cast<char>(dict.size() & 0xff);
  npy += static_cast<char>(dict.size() >> 8);
  npy += dict + std::string(24, '\0');
  const std::string p = (dir / "huge.npy").string();
  std::ofstream(p, std::ios::binary) << npy;
  testing::ExpectInputError([&] { ReadNpy(p); }, {"huge.npy", "shape"});
  fs::remove_all(dir);
}

// A UTF-8 byte-order mark before the first vertex: the face indices count it.
TEST(ReaderFuzz, ObjWithByteOrderMark) {
  const fs::path p = fs::temp_directory_path() / ("arcs_bom_" + std::to_string(getpid()) + ".obj");
  std::ofstream(p, std::ios::binary) << "\xEF\xBB\xBFv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  const Mesh m = ReadMesh(p.string());
  EXPECT_EQ(m.NumVertices(), 3);
  EXPECT_EQ(m.NumFaces(), 1);
  fs::remove(p);
}

}  // namespace
}  // namespace arcs
