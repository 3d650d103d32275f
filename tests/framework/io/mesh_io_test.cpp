#include "framework/io/mesh_io.h"

#include "framework/error.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <bit>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

namespace arcs {
namespace {

namespace fs = std::filesystem;

using testing::WriteFile;

// Runs f, expecting an InputError whose message is "FILE:LINE: ..." and
// contains `what`.
template <class F>
void ExpectLineError(F&& f, const std::string& file, long line, const std::string& what) {
  try {
    f();
    ADD_FAILURE() << "no exception; expected " << file << ":" << line << ": " << what;
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(e.line(), line) << msg;
    EXPECT_NE(msg.find(file + ":" + std::to_string(line) + ": "), std::string::npos) << msg;
    EXPECT_NE(msg.find(what), std::string::npos) << msg;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "wrong exception type: " << e.what();
  }
}

// Runs f, expecting an InputError "FILE: offset N: ..." containing `what`.
template <class F>
void ExpectOffsetError(F&& f, const std::string& file, long offset, const std::string& what) {
  try {
    f();
    ADD_FAILURE() << "no exception; expected offset " << offset << ": " << what;
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(file + ": offset " + std::to_string(offset) + ": "), std::string::npos)
        << msg;
    EXPECT_NE(msg.find(what), std::string::npos) << msg;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "wrong exception type: " << e.what();
  }
}

// An octahedron with coordinates that are not short decimals, so a text
// round trip is exact only if every digit needed is written.
Mesh Octahedron() {
  Mesh m;
  m.V.resize(6, 3);
  const double a = 1.0 / 3.0, b = M_PI, c = -2.5e-7;
  m.V << a, 0, 0,  //
      -b, 0, 0,    //
      0, a * b, 0, //
      0, -1e10, c, //
      0, 0, 0.1,   //
      0, 0, -0.7;
  m.F.resize(8, 3);
  m.F << 0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5;
  return m;
}

// Float-exact coordinates for STL (float32 on disk).
Mesh FloatOctahedron() {
  Mesh m = Octahedron();
  m.V << 0.5, 0, 0, -1.25, 0, 0, 0, 0.75, 0, 0, -3, 0, 0, 0, 1, 0, -0.0, -2;
  return m;
}

TEST(MeshIoTest, TextAndPlyRoundTripsAreExact) {
  const auto dir = testing::TempDir("mesh_io_roundtrip");
  const Mesh m = Octahedron();
  for (const char* ext : {".obj", ".off", ".ply", ".OBJ"}) {
    const std::string path = (dir / (std::string("octa") + ext)).string();
    WriteMesh(path, m);
    MeshReadReport rep;
    const Mesh r = ReadMesh(path, &rep);
    ASSERT_EQ(r.NumVertices(), 6) << ext;
    ASSERT_EQ(r.NumFaces(), 8) << ext;
    EXPECT_TRUE(r.V == m.V) << ext;  // bitwise equal doubles
    EXPECT_TRUE(r.F == m.F) << ext;
    EXPECT_EQ(rep.unreferenced_vertices, 0);
    EXPECT_EQ(rep.degenerate_faces, 0);
    EXPECT_EQ(rep.polygons_triangulated, 0);
    EXPECT_TRUE(rep.warnings.empty()) << rep.warnings[0];
  }
}

TEST(MeshIoTest, StlRoundTripWeldsTheSoupBack) {
  const auto dir = testing::TempDir("mesh_io_stl");
  const Mesh m = FloatOctahedron();
  const std::string path = (dir / "octa.stl").string();
  WriteMesh(path, m);
  EXPECT_EQ(fs::file_size(path), 84u + 50u * 8u);
  MeshReadReport rep;
  const Mesh r = ReadMesh(path, &rep);
  ASSERT_EQ(r.NumVertices(), 6);
  ASSERT_EQ(r.NumFaces(), 8);
  EXPECT_EQ(rep.welded_vertices, 3 * 8 - 6);
  // Faces keep their order and corners; vertices are numbered by first use.
  for (int f = 0; f < 8; ++f) {
    for (int k = 0; k < 3; ++k) {
      EXPECT_TRUE(r.V.row(r.F(f, k)) == m.V.row(m.F(f, k))) << f << " " << k;
    }
  }
}

TEST(MeshIoTest, ObjPolygonsSlashesNegativeIndicesAndIgnoredStatements) {
  const auto dir = testing::TempDir("mesh_io_obj");
  const std::string path = (dir / "quad.obj").string();
  WriteFile(path,
            "# a comment\n"
            "mtllib x.mtl\no cube\ng side\ns off\nusemtl red\n"
            "v 0 0 0\nv 1 0 0\r\nv 1 1 0\n"
            "vt 0 0\nvn 0 0 1\n"
            "v 0 1 0 1.0\n"  // optional w
            "f 1/1/1 2/1/1 3//1 4\n"
            "\t f -4 -2 -1\n"
            "l 1 2\n");
  MeshReadReport rep;
  const Mesh r = ReadMesh(path, &rep);
  ASSERT_EQ(r.NumVertices(), 4);
  ASSERT_EQ(r.NumFaces(), 3);
  EXPECT_EQ(rep.polygons_triangulated, 1);
  Eigen::Matrix<int, 3, 3, Eigen::RowMajor> expect;
  expect << 0, 1, 2, 0, 2, 3, 0, 2, 3;
  EXPECT_TRUE(r.F == expect) << r.F;
  EXPECT_EQ(r.V(3, 1), 1.0);
  EXPECT_TRUE(rep.warnings.size() == 1) << ::testing::PrintToString(rep.warnings);  // triangulated
}

TEST(MeshIoTest, ObjRationalCoordinatesAreExactQuotients) {
  const auto dir = testing::TempDir("mesh_io_rational");
  const std::string path = (dir / "r.obj").string();
  WriteFile(path,
            "v 1/3 -7/2 0/1\nv 7299584583679663/562949953421312 1 2\nv 0 1 0\nf 1 2 3\n");
  MeshReadReport rep;
  const Mesh r = ReadMesh(path, &rep);
  EXPECT_EQ(rep.rational_coordinates, 4);
  EXPECT_EQ(r.V(0, 0), 1.0 / 3.0);
  EXPECT_EQ(r.V(0, 1), -3.5);
  EXPECT_EQ(r.V(0, 2), 0.0);
  EXPECT_EQ(r.V(1, 0), 7299584583679663.0 / 562949953421312.0);
}

TEST(MeshIoTest, ObjErrorsNameFileAndLine) {
  const auto dir = testing::TempDir("mesh_io_obj_bad");
  struct Case {
    std::string body;
    long line;
    std::string what;
  };
  const std::vector<Case> cases = {
      {"v 0 0 0\nv 1 0\n", 2, "2 coordinates"},
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\n# c\nf 1 2 4\n", 5, "index 4 out of range"},
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", 4, "index 0"},
      {"v 0 0 0\nv nan 0 0\n", 2, "non-finite"},
      {"v 0 0 0\nv 0 inf 0\n", 2, "non-finite"},
      {"v 0 0 0\n\nv 1e999 0 0\n", 3, "out of the double range"},
      {"v 0 0 0\nv 0 x 0\n", 2, "bad vertex coordinate 'x'"},
      {"v 0 0 0\nv 1 0 0\nf 1 2\n", 3, "at least 3"},
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 a 3\n", 4, "bad face vertex 'a'"},
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 1 2\n", 4, "refers before the first vertex"},
      {"v 1/0 0 0\n", 1, "bad vertex coordinate"},
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 99999999999\n", 5, "out of range"},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const std::string path = (dir / ("bad" + std::to_string(i) + ".obj")).string();
    WriteFile(path, cases[i].body);
    ExpectLineError([&] { ReadMesh(path); }, path, cases[i].line, cases[i].what);
  }
  // A binary file with an .obj name is not parsed as text.
  const std::string bin = (dir / "binary.obj").string();
  WriteFile(bin, std::string("v 0 0 0\nv 1 0 0\n\x01\x00\x02", 19));
  ExpectLineError([&] { ReadMesh(bin); }, bin, 3, "binary data");
}

TEST(MeshIoTest, OffHeaderVariantsAndComments) {
  const auto dir = testing::TempDir("mesh_io_off");
  const std::string a = (dir / "a.off").string();
  WriteFile(a, "OFF 4 2 0\n# comment\n0 0 0\n1 0 0 # trailing comment\n1 1 0\n0 1 0\n4 0 1 2 3\n"
               "3 0 2 3 255 0 0\n");
  MeshReadReport rep;
  Mesh m = ReadMesh(a, &rep);
  EXPECT_EQ(m.NumVertices(), 4);
  EXPECT_EQ(m.NumFaces(), 3);
  EXPECT_EQ(rep.polygons_triangulated, 1);

  const std::string b = (dir / "b.off").string();  // COFF, counts on the next line, no E
  WriteFile(b, "COFF\n\n3 1\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n0 1 0 0 0 255 255\n3 0 1 2\n");
  m = ReadMesh(b);
  EXPECT_EQ(m.NumVertices(), 3);
  EXPECT_EQ(m.NumFaces(), 1);
  EXPECT_EQ(m.V(1, 0), 1.0);

  const std::string c = (dir / "c.off").string();  // NOFF with normals, CRLF
  WriteFile(c, "NOFF\r\n3 1 3\r\n0 0 0 0 0 1\r\n1 0 0 0 0 1\r\n0 1 0 0 0 1\r\n3 2 1 0\r\n");
  m = ReadMesh(c);
  ASSERT_EQ(m.NumFaces(), 1);
  EXPECT_EQ(m.F(0, 0), 2);
}

TEST(MeshIoTest, OffErrorsNameFileAndLine) {
  const auto dir = testing::TempDir("mesh_io_off_bad");
  struct Case {
    std::string body;
    long line;
    std::string what;
  };
  const std::vector<Case> cases = {
      // truncated: the error names the last line, where the data runs out
      {"OFF\n3 1 0\n0 0 0\n1 0 0\n", 4, "expected 3 vertices, found 2"},
      {"OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", 6, "expected 2 faces, found 1"},
      {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", 6, "out of range [0, 3)"},
      {"OFF\n3 1 0\n0 0 0\n1 0\n0 1 0\n3 0 1 2\n", 4, "2 coordinates"},
      {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n", 6, "announces 4 vertices but lists 3"},
      {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n", 6, "at least 3"},
      {"OFF\nthree 1 0\n", 2, "counts"},
      {"PLY\n3 1 0\n", 1, "not an OFF file"},
      {"4OFF\n3 1 0\n", 1, "not supported"},
      {"OFF BINARY\n3 1 0\n", 1, "binary OFF"},
      {"OFF\n3 1 0\n0 0 0\n1 -nan 0\n0 1 0\n3 0 1 2\n", 4, "non-finite"},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const std::string path = (dir / ("bad" + std::to_string(i) + ".off")).string();
    WriteFile(path, cases[i].body);
    ExpectLineError([&] { ReadMesh(path); }, path, cases[i].line, cases[i].what);
  }
}

TEST(MeshIoTest, LyingHeadersFailFastWithoutAllocating) {
  const auto dir = testing::TempDir("mesh_io_lying");
  const auto t0 = std::chrono::steady_clock::now();
  const std::string off_v = (dir / "v.off").string();
  WriteFile(off_v, "OFF\n1000000000000 1 0\n0 0 0\n");
  ExpectLineError([&] { ReadMesh(off_v); }, off_v, 2, "2^31");
  const std::string off_f = (dir / "f.off").string();
  WriteFile(off_f, "OFF\n3 1000000000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  ExpectLineError([&] { ReadMesh(off_f); }, off_f, 6, "expected 1000000000000 faces, found 1");
  const std::string ply_a = (dir / "a.ply").string();
  WriteFile(ply_a, "ply\nformat ascii 1.0\nelement vertex 1000000000\nproperty float x\n"
                   "property float y\nproperty float z\nend_header\n0 0 0\n");
  ExpectLineError([&] { ReadMesh(ply_a); }, ply_a, 8,
                  "unexpected end of file in element 'vertex' entry 1 of 1000000000");
  const std::string ply_b = (dir / "b.ply").string();
  WriteFile(ply_b, "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
                   "property float y\nproperty float z\nelement face 1000000000000\n"
                   "property list uchar int vertex_indices\nend_header\n" +
                       std::string(36, '\0') + std::string(13, '\0'));
  ExpectLineError([&] { ReadMesh(ply_b); }, ply_b, 7, "claims 1000000000000 entries");
  const std::string stl = (dir / "s.stl").string();
  std::string s(80, ' ');
  s += std::string("\xff\xff\xff\x7f", 4);  // 2^31 - 1 triangles
  s += std::string(50, '\0');
  WriteFile(stl, s);
  ExpectOffsetError([&] { ReadMesh(stl); }, stl, 80, "2147483647 triangles");
  const double secs =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(secs, 1.0);
}

// Appends a scalar in big-endian byte order.
template <class T>
void PutBE(std::string* s, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if constexpr (std::endian::native == std::endian::little) {
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
  }
  s->append(b, sizeof(T));
}
template <class T>
void PutLE(std::string* s, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if constexpr (std::endian::native == std::endian::big) {
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
  }
  s->append(b, sizeof(T));
}

TEST(MeshIoTest, PlyAsciiSkipsUnknownPropertiesAndElements) {
  const auto dir = testing::TempDir("mesh_io_ply_ascii");
  const std::string path = (dir / "a.ply").string();
  WriteFile(path,
            "ply\r\nformat ascii 1.0\ncomment hi\nobj_info x\n"
            "element material 1\nproperty list uchar float rgb\n"
            "element vertex 4\nproperty uchar red\nproperty short x\nproperty double y\n"
            "property list int int junk\nproperty float z\nproperty uint conf\n"
            "element face 2\nproperty list ushort uint vertex_index\nproperty int flags\n"
            "element edge 1\nproperty int a\nproperty int b\nend_header\n"
            "3 0.1 0.2 0.3\n"
            "255 0 0 2 7 8 0 1\n"
            "0 1 0 0 0 9\n"
            "1 1 1.5 1 5 0 3\n"
            "2 -7 1.5e3 0 -0.25 4\n"
            "4 0 1 2 3 77\n"
            "3 3 2 1 0\n"
            "0 1\n");
  MeshReadReport rep;
  const Mesh m = ReadMesh(path, &rep);
  ASSERT_EQ(m.NumVertices(), 4);
  ASSERT_EQ(m.NumFaces(), 3);
  EXPECT_EQ(rep.polygons_triangulated, 1);
  EXPECT_EQ(m.V(1, 1), 0.0);
  EXPECT_EQ(m.V(2, 1), 1.5);
  EXPECT_EQ(m.V(3, 0), -7.0);
  EXPECT_EQ(m.V(3, 1), 1500.0);
  EXPECT_EQ(m.V(3, 2), -0.25);
  EXPECT_EQ(m.F(2, 0), 3);
  EXPECT_EQ(m.F(2, 2), 1);
}

TEST(MeshIoTest, PlyBinaryBigAndLittleEndianAnyTypes) {
  const auto dir = testing::TempDir("mesh_io_ply_bin");
  for (bool big : {true, false}) {
    auto put_f = [&](std::string* s, float v) { big ? PutBE(s, v) : PutLE(s, v); };
    auto put_d = [&](std::string* s, double v) { big ? PutBE(s, v) : PutLE(s, v); };
    auto put_u32 = [&](std::string* s, std::uint32_t v) { big ? PutBE(s, v) : PutLE(s, v); };
    auto put_i16 = [&](std::string* s, std::int16_t v) { big ? PutBE(s, v) : PutLE(s, v); };
    std::string s = std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
                    " 1.0\nelement vertex 4\nproperty double x\nproperty float y\n"
                    "property list uchar short junk\nproperty int16 z\nproperty float64 w\n"
                    "element face 2\nproperty uchar flag\nproperty list ushort uint vertex_indices\n"
                    "element extra 2\nproperty list uint uchar bytes\nend_header\n";
    const double xs[4] = {0.1, -2.0, 3.0, 1e-300};
    for (int v = 0; v < 4; ++v) {
      put_d(&s, xs[v]);
      put_f(&s, static_cast<float>(v) * 0.5f);
      s += static_cast<char>(v);  // junk list length
      for (int j = 0; j < v; ++j) put_i16(&s, static_cast<std::int16_t>(-j));
      put_i16(&s, static_cast<std::int16_t>(-v));
      put_d(&s, 42.0);
    }
    s += '\x01';
    big ? PutBE<std::uint16_t>(&s, 4) : PutLE<std::uint16_t>(&s, 4);
    for (std::uint32_t i : {0u, 1u, 2u, 3u}) put_u32(&s, i);
    s += '\x00';
    big ? PutBE<std::uint16_t>(&s, 3) : PutLE<std::uint16_t>(&s, 3);
    for (std::uint32_t i : {3u, 1u, 0u}) put_u32(&s, i);
    put_u32(&s, 2);
    s += "ab";
    put_u32(&s, 0);
    const std::string path = (dir / (big ? "be.ply" : "le.ply")).string();
    WriteFile(path, s);
    MeshReadReport rep;
    const Mesh m = ReadMesh(path, &rep);
    ASSERT_EQ(m.NumVertices(), 4);
    ASSERT_EQ(m.NumFaces(), 3);
    for (int v = 0; v < 4; ++v) {
      EXPECT_EQ(m.V(v, 0), xs[v]);
      EXPECT_EQ(m.V(v, 1), v * 0.5);
      EXPECT_EQ(m.V(v, 2), -v);
    }
    EXPECT_EQ(m.F(2, 0), 3);
    EXPECT_EQ(m.F(2, 1), 1);
    EXPECT_EQ(m.F(2, 2), 0);
    EXPECT_EQ(rep.polygons_triangulated, 1);

    // Truncate inside the face list: binary errors name the byte offset.
    const std::string cut = (dir / (big ? "be_cut.ply" : "le_cut.ply")).string();
    const std::size_t header = s.find("end_header\n") + 11;
    const std::size_t vbytes = 4 * (8 + 4 + 1 + 2 + 8) + 2 * (0 + 1 + 2 + 3);
    WriteFile(cut, s.substr(0, header + vbytes + 1 + 2 + 8));
    ExpectOffsetError([&] { ReadMesh(cut); }, cut, static_cast<long>(header + vbytes + 1),
                      "runs past the end of file");
  }
}

TEST(MeshIoTest, PlyErrors) {
  const auto dir = testing::TempDir("mesh_io_ply_bad");
  const std::string head =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  struct Case {
    std::string body;
    long line;
    std::string what;
  };
  const std::vector<Case> cases = {
      {head + "0 0 0\n1 0 0\n0 1 0\n3 0 1 5\n", 13, "out of range [0, 3)"},
      {head + "0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n", 11, "non-finite"},
      {head + "0 0 0\n1 0 0\n0 1 0\n3 0 1\n", 13, "unexpected end of file"},
      {head + "0 0 0\n1 0 0\n0 1 0\n3 0 1 -1\n", 13, "out of range"},
      {head + "0 0 0\n1 0 0\n0 1 zz\n3 0 1 2\n", 12, "bad number 'zz'"},
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n"
       "0 0\n", 3, "needs properties x, y and z"},
      {"ply\nformat binary_middle_endian 1.0\n", 2, "unknown PLY format"},
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\n", 4, "unknown PLY type"},
      {"ply\nformat ascii 1.0\nelement vertex 0\n", 3, "no 'end_header'"},
      {"obj\n", 1, "not a PLY file"},
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty "
       "float z\nelement face 1\nproperty list float int vertex_indices\nend_header\n",
       8, "integer type"},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const std::string path = (dir / ("bad" + std::to_string(i) + ".ply")).string();
    WriteFile(path, cases[i].body);
    ExpectLineError([&] { ReadMesh(path); }, path, cases[i].line, cases[i].what);
  }
  // Binary: a NaN coordinate is reported at the vertex's byte offset.
  std::string b = "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\n"
                  "property float y\nproperty float z\nend_header\n";
  const std::size_t h = b.size();
  for (float v : {0.f, 1.f, 2.f, 3.f, std::nanf(""), 5.f}) PutLE(&b, v);
  const std::string path = (dir / "nan.ply").string();
  WriteFile(path, b);
  ExpectOffsetError([&] { ReadMesh(path); }, path, static_cast<long>(h + 12), "vertex 1");
}

TEST(MeshIoTest, StlAsciiAndBinaryDetection) {
  const auto dir = testing::TempDir("mesh_io_stl_detect");
  const std::string a = (dir / "a.stl").string();
  WriteFile(a,
            "solid square\n"
            " facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n"
            "   vertex 1 1 0\n  endloop\n endfacet\n"
            " FACET NORMAL 0 0 1\n  OUTER LOOP\n   VERTEX 0 0 0\n   VERTEX 1 1 0\n"
            "   VERTEX 0 1 -0\n  ENDLOOP\n ENDFACET\n"
            "endsolid square\n");
  MeshReadReport rep;
  Mesh m = ReadMesh(a, &rep);
  EXPECT_EQ(m.NumVertices(), 4);
  EXPECT_EQ(m.NumFaces(), 2);
  EXPECT_EQ(rep.welded_vertices, 2);

  // A binary STL whose 80-byte header starts with "solid" is still binary.
  std::string b = "solid but binary";
  b.resize(80, ' ');
  PutLE<std::uint32_t>(&b, 1);
  for (float v : {0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) PutLE(&b, v);
  PutLE<std::uint16_t>(&b, 0);
  const std::string bp = (dir / "b.STL").string();
  WriteFile(bp, b);
  m = ReadMesh(bp);
  EXPECT_EQ(m.NumVertices(), 3);
  EXPECT_EQ(m.NumFaces(), 1);
  EXPECT_EQ(m.V(2, 1), 1.0);

  // Truncated binary starting with "solid": binary data -> clear error.
  const std::string cut = (dir / "cut.stl").string();
  WriteFile(cut, b.substr(0, b.size() - 10));
  ExpectOffsetError([&] { ReadMesh(cut); }, cut, 80, "does not match a binary STL");

  // NaN in a binary STL: offset of the coordinate.
  std::string n = b;
  const float nan = std::nanf("");
  std::memcpy(n.data() + 84 + 12 + 4 * 4, &nan, 4);
  const std::string np = (dir / "nan.stl").string();
  WriteFile(np, n);
  ExpectOffsetError([&] { ReadMesh(np); }, np, 84 + 12 + 16, "non-finite");

  const std::string bad = (dir / "bad.stl").string();
  WriteFile(bad, "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\n");
  ExpectLineError([&] { ReadMesh(bad); }, bad, 6, "2 vertices");
  const std::string junk = (dir / "junk.stl").string();
  WriteFile(junk, "solid x\nfacet normal 0 0 1\nouter loop\nvortex 0 0 0\n");
  ExpectLineError([&] { ReadMesh(junk); }, junk, 4, "'vortex'");
}

TEST(MeshIoTest, ExtensionsMissingFilesAndUnwritablePaths) {
  const auto dir = testing::TempDir("mesh_io_misc");
  const std::string missing = (dir / "nope.obj").string();
  try {
    ReadMesh(missing);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot open"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos);
  }
  const std::string unk = (dir / "mesh.gltf").string();
  WriteFile(unk, "{}");
  try {
    ReadMesh(unk);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(".obj .off .ply .stl"), std::string::npos) << e.what();
  }
  EXPECT_THROW(WriteMesh((dir / "no_such_dir" / "m.obj").string(), Octahedron()), Error);
  Mesh bad = Octahedron();
  bad.F(0, 0) = 6;
  EXPECT_THROW(WriteMesh((dir / "m.obj").string(), bad), Error);
  bad = Octahedron();
  bad.V(0, 0) = std::nan("");
  EXPECT_THROW(WriteMesh((dir / "m.ply").string(), bad), Error);
  EXPECT_FALSE(fs::exists(dir / "m.obj"));
  EXPECT_FALSE(fs::exists(dir / "m.ply"));
}

// ---- shared data ------------------------------------------------------------

void ExpectValidMesh(const Mesh& m, const std::string& name) {
  EXPECT_TRUE(m.V.allFinite()) << name;
  if (m.NumFaces() > 0) {
    EXPECT_GE(m.F.minCoeff(), 0) << name;
    EXPECT_LT(m.F.maxCoeff(), m.NumVertices()) << name;
  }
}

TEST(MeshIoSharedDataTest, EveryBadFileLoadsCleanlyOrThrowsInputError) {
  ARCS_REQUIRE_SHARED_DATA();
  int loaded = 0, rejected = 0;
  for (const auto& entry : fs::directory_iterator(testing::SharedData("bad"))) {
    const std::string path = entry.path().string();
    if (entry.path().filename() == "MANIFEST.tsv") continue;
    try {
      MeshReadReport rep;
      const Mesh m = ReadMesh(path, &rep);
      ExpectValidMesh(m, path);
      ++loaded;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
      ++rejected;
    } catch (const std::exception& e) {
      ADD_FAILURE() << path << ": not an InputError: " << e.what();
    }
  }
  EXPECT_GE(loaded, 15);
  EXPECT_GE(rejected, 2);  // invalid.off, malformed.obj
}

TEST(MeshIoSharedDataTest, SpecificBadFiles) {
  ARCS_REQUIRE_SHARED_DATA();
  const std::string invalid = testing::SharedData("bad/invalid.off");
  ExpectLineError([&] { ReadMesh(invalid); }, invalid, 6, "0 vertices");
  const std::string malformed = testing::SharedData("bad/malformed.obj");
  ExpectLineError([&] { ReadMesh(malformed); }, malformed, 23, "index 12 out of range");

  MeshReadReport rep;
  const Mesh r = ReadMesh(testing::SharedData("bad/rational_coords.obj"), &rep);
  EXPECT_GT(rep.rational_coordinates, 0);
  EXPECT_EQ(rep.rational_coordinates, 3 * r.NumVertices());
  EXPECT_TRUE(r.V.allFinite());
  // First vertex: 7299584583679663/562949953421312 -6500387615755517/4503599627370496 ...
  EXPECT_EQ(r.V(0, 0), 7299584583679663.0 / 562949953421312.0);
  EXPECT_EQ(r.V(0, 1), -6500387615755517.0 / 4503599627370496.0);

  // Binary STL whose header begins with "solid": detected by its size.
  rep = MeshReadReport();
  const Mesh holes = ReadMesh(testing::SharedData("bad/thingi50736_holes.stl"), &rep);
  EXPECT_EQ(holes.NumFaces(), 420);
  EXPECT_EQ(holes.NumVertices(), 278);
  EXPECT_EQ(rep.welded_vertices, 3 * 420 - 278);

  // Binary PLY with normals and a uchar/int face list.
  const Mesh horse = ReadMesh(testing::SharedData("bad/horse_inward.ply"));
  EXPECT_EQ(horse.NumVertices(), 48485);
  EXPECT_EQ(horse.NumFaces(), 96966);

  rep = MeshReadReport();
  const Mesh bunny = ReadMesh(testing::SharedData("bad/stanford_bunny_open.obj"), &rep);
  EXPECT_EQ(bunny.NumVertices(), 35947);
  EXPECT_EQ(rep.unreferenced_vertices, 1113);
}

// Columns of a MANIFEST.tsv by header name.
std::vector<std::map<std::string, std::string>> ReadManifest(const std::string& path) {
  std::ifstream f(path);
  std::string line;
  std::vector<std::string> cols;
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(f, line)) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, '\t')) cells.push_back(cell);
    if (cols.empty()) {
      cols = cells;
      continue;
    }
    std::map<std::string, std::string> row;
    for (std::size_t i = 0; i < cols.size() && i < cells.size(); ++i) row[cols[i]] = cells[i];
    rows.push_back(row);
  }
  return rows;
}

TEST(MeshIoSharedDataTest, TinyMeshesMatchManifestCounts) {
  ARCS_REQUIRE_SHARED_DATA();
  const auto rows = ReadManifest(testing::SharedData("tiny/MANIFEST.tsv"));
  ASSERT_GE(rows.size(), 5u);
  for (const auto& row : rows) {
    const std::string path = testing::SharedData("tiny/" + row.at("file"));
    MeshReadReport rep;
    const Mesh m = ReadMesh(path, &rep);
    EXPECT_EQ(m.NumVertices(), std::stoi(row.at("V"))) << path;
    EXPECT_EQ(m.NumFaces(), std::stoi(row.at("F"))) << path;
    ExpectValidMesh(m, path);
  }
}

TEST(MeshIoSharedDataTest, BenchBunnyReadsFast) {
  ARCS_REQUIRE_SHARED_DATA();
  const std::string path = testing::SharedData("bench/bunny_fixed.obj");
  const auto t0 = std::chrono::steady_clock::now();
  const Mesh m = ReadMesh(path);
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(m.NumVertices(), 35189);
  EXPECT_EQ(m.NumFaces(), 70374);
#ifdef NDEBUG
  EXPECT_LT(secs, 0.5);
#else
  EXPECT_LT(secs, 3.0);
#endif
  RecordProperty("read_seconds", std::to_string(secs));
}

}  // namespace
}  // namespace arcs
