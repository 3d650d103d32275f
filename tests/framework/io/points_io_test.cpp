#include "framework/io/points_io.h"

#include "framework/error.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

namespace arcs {
namespace {

namespace fs = std::filesystem;

using testing::WriteFile;


template <class T>
void PutLE(std::string* s, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  s->append(b, sizeof(T));  // the test machines are little endian (checked below)
}

PointCloud Cloud(bool normals) {
  PointCloud pc;
  pc.P.resize(4, 3);
  pc.P << 1.0 / 3.0, 0, -1e-7, M_PI, 2, 3, -0.0, 1e300, 5, 0.1, 0.2, 0.3;
  if (normals) {
    pc.N.resize(4, 3);
    pc.N << 1, 0, 0, 0, 1, 0, 0, 0, -1, std::sqrt(1.0 / 3), std::sqrt(1.0 / 3), std::sqrt(1.0 / 3);
  }
  return pc;
}

TEST(PointsIoTest, RoundTripsAreExact) {
  static_assert(std::endian::native == std::endian::little);
  const auto dir = testing::TempDir("points_io_roundtrip");
  for (bool normals : {false, true}) {
    for (const char* ext : {".ply", ".xyz", ".pwn"}) {
      const PointCloud pc = Cloud(normals);
      const std::string path = (dir / (std::string("c") + ext)).string();
      WritePointCloud(path, pc);
      PointReadReport rep;
      const PointCloud r = ReadPointCloud(path, &rep);
      EXPECT_TRUE(r.P == pc.P) << ext;
      EXPECT_EQ(r.HasNormals(), normals) << ext;
      if (normals) {
        EXPECT_TRUE(r.N == pc.N) << ext;
      }
      EXPECT_TRUE(rep.skipped_lines.empty());
      EXPECT_TRUE(rep.warnings.empty());
    }
  }
  EXPECT_THROW(WritePointCloud((dir / "nodir" / "c.xyz").string(), Cloud(true)), Error);
  testing::ExpectInputError([&] { WritePointCloud((dir / "c.las").string(), Cloud(false)); }, {".ply .xyz"});
}

TEST(PointsIoTest, XyzSkipsAndReportsMalformedLines) {
  const auto dir = testing::TempDir("points_io_xyz");
  const std::string path = (dir / "a.xyz").string();
  WriteFile(path,
            "# header comment\n"        // 1
            "0 0 0 0 0 1\n"             // 2 valid, decides 6 columns
            "1 2 3\n"                   // 3 wrong column count
            "\n"                        // 4 blank (not reported)
            "4 5 6 0 1 0\r\n"           // 5 valid
            "7 8 nine 0 0 1\n"          // 6 not a number
            "1 1 1 nan 0 0\n"           // 7 non-finite
            "1 2 3 4 5 6 7\n"           // 8 too many
            "-1 -2 -3 1 0 0 # ok\n");   // 9 valid
  PointReadReport rep;
  const PointCloud pc = ReadPointCloud(path, &rep);
  ASSERT_EQ(pc.Size(), 3);
  ASSERT_TRUE(pc.HasNormals());
  EXPECT_EQ(pc.P(1, 2), 6.0);
  EXPECT_EQ(pc.N(2, 0), 1.0);
  EXPECT_EQ(rep.skipped_lines, (std::vector<long>{3, 6, 7, 8}));
  EXPECT_FALSE(rep.warnings.empty());

  const std::string three = (dir / "b.txt").string();
  WriteFile(three, "1 2 3\n4 5 6\n");
  const PointCloud p3 = ReadPointCloud(three);
  EXPECT_EQ(p3.Size(), 2);
  EXPECT_FALSE(p3.HasNormals());

  const std::string none = (dir / "c.xyz").string();
  WriteFile(none, "# nothing\nhello world\n1 2\n");
  testing::ExpectInputError([&] { ReadPointCloud(none); }, {none + ":2:", "no valid point line"});
}

TEST(PointsIoTest, PlyPointsWithNormalsFacesIgnoredNonFiniteSkipped) {
  const auto dir = testing::TempDir("points_io_ply");
  const std::string path = (dir / "a.ply").string();
  WriteFile(path,
            "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
            "property float z\nproperty float normal_x\nproperty float normal_y\n"
            "property float normal_z\nproperty uchar red\nelement face 1\n"
            "property list uchar int vertex_indices\nend_header\n"
            "0 0 0 0 0 1 5\n"        // 14
            "1 0 0 0 0 1 5\n"        // 15
            "1 nan 0 0 0 1 5\n"      // 16
            "0 1 0 0 0 1 5\n"        // 17
            "3 0 1 2\n");
  PointReadReport rep;
  const PointCloud pc = ReadPointCloud(path, &rep);
  ASSERT_EQ(pc.Size(), 3);
  ASSERT_TRUE(pc.HasNormals());
  EXPECT_EQ(pc.P(2, 1), 1.0);
  EXPECT_EQ(rep.skipped_lines, std::vector<long>{16});

  // Binary: skipped points are reported with a byte offset.
  std::string b = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty double x\n"
                  "property double y\nproperty double z\nend_header\n";
  const std::size_t h = b.size();
  for (double v : {0.0, 0.0, 0.0, 1.0, double(INFINITY), 0.0, 2.0, 0.0, 0.0}) PutLE(&b, v);
  const std::string bp = (dir / "b.ply").string();
  WriteFile(bp, b);
  rep = PointReadReport();
  const PointCloud pb = ReadPointCloud(bp, &rep);
  EXPECT_EQ(pb.Size(), 2);
  EXPECT_EQ(pb.P(1, 0), 2.0);
  ASSERT_EQ(rep.warnings.size(), 1u);
  EXPECT_NE(rep.warnings[0].find("offset " + std::to_string(h + 24)), std::string::npos)
      << rep.warnings[0];

  const std::string cut = (dir / "cut.ply").string();
  WriteFile(cut, b.substr(0, b.size() - 4));
  testing::ExpectInputError([&] { ReadPointCloud(cut); }, {cut + ":3:", "claims 3 entries"});
}

TEST(PointsIoTest, PcdAsciiAndBinary) {
  const auto dir = testing::TempDir("points_io_pcd");
  const std::string header =
      "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z rgb normal_x normal_y normal_z curvature\n"
      "SIZE 4 4 4 4 4 4 4 4\nTYPE F F F U F F F F\nCOUNT 1 1 1 1 1 1 1 1\nWIDTH 3\nHEIGHT 1\n"
      "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\n";
  const std::string a = (dir / "a.pcd").string();
  WriteFile(a, header + "DATA ascii\n"
                        "0.5 1 2 255 0 0 1 0.01\n"   // 12
                        "nan nan nan 0 0 0 1 0\n"    // 13
                        "3 4 5 0 0 1 0 0.5\n");      // 14
  PointReadReport rep;
  PointCloud pc = ReadPointCloud(a, &rep);
  ASSERT_EQ(pc.Size(), 2);
  ASSERT_TRUE(pc.HasNormals());
  EXPECT_EQ(pc.P(0, 0), 0.5);
  EXPECT_EQ(pc.N(1, 1), 1.0);
  EXPECT_EQ(rep.skipped_lines, std::vector<long>{13});

  std::string b = header + "DATA binary\n";
  const std::size_t h = b.size();
  const float pts[3][7] = {{0.5f, 1, 2, 0, 0, 1, 0.f},
                           {NAN, NAN, NAN, 0, 0, 1, 0.f},
                           {3, 4, 5, 0, 1, 0, 0.5f}};
  for (const auto& p : pts) {
    for (int k = 0; k < 3; ++k) PutLE(&b, p[k]);
    PutLE<std::uint32_t>(&b, 0xffffffu);
    for (int k = 3; k < 7; ++k) PutLE(&b, p[k]);
  }
  const std::string bp = (dir / "b.pcd").string();
  WriteFile(bp, b);
  rep = PointReadReport();
  pc = ReadPointCloud(bp, &rep);
  ASSERT_EQ(pc.Size(), 2);
  EXPECT_EQ(pc.P(1, 2), 5.0);
  EXPECT_EQ(pc.N(1, 1), 1.0);
  ASSERT_EQ(rep.warnings.size(), 1u);
  EXPECT_NE(rep.warnings[0].find("offset " + std::to_string(h + 32)), std::string::npos);

  // Errors.
  const std::string c = (dir / "c.pcd").string();
  WriteFile(c, header + "DATA binary_compressed\n\x01\x02");
  // (binary_compressed is read since issue 14: two bytes are no size header.)
  testing::ExpectInputError([&] { ReadPointCloud(c); }, {c + ": offset", "no size header"});
  const std::string d = (dir / "d.pcd").string();
  WriteFile(d, b.substr(0, b.size() - 1));
  testing::ExpectInputError([&] { ReadPointCloud(d); }, {d + ": offset " + std::to_string(h), "shorter"});
  const std::string lie = (dir / "lie.pcd").string();
  std::string lying = header + "DATA ascii\n0 0 0 0 0 0 1 0\n";
  lying.replace(lying.find("POINTS 3"), 8, "POINTS 1000000000000");
  WriteFile(lie, lying);
  testing::ExpectInputError([&] { ReadPointCloud(lie); }, {lie + ":12:", "expected 1000000000000 points, found 1"});
  const std::string shortf = (dir / "short.pcd").string();
  WriteFile(shortf, header + "DATA ascii\n0 0 0 0 0 0 1 0\n1 1 1 0 0 0 1\n");
  testing::ExpectInputError([&] { ReadPointCloud(shortf); }, {shortf + ":13:", "expected 8 values"});
  const std::string noxyz = (dir / "noxyz.pcd").string();
  WriteFile(noxyz, "FIELDS a b c\nSIZE 4 4 4\nTYPE F F F\nPOINTS 0\nDATA ascii\n");
  testing::ExpectInputError([&] { ReadPointCloud(noxyz); }, {noxyz + ":1:", "x, y and z"});
}

TEST(PointsIoTest, UnknownExtensionAndMissingFile) {
  const auto dir = testing::TempDir("points_io_misc");
  testing::ExpectInputError([&] { ReadPointCloud((dir / "a.las").string()); }, {"a.las", ".ply .xyz"});
  testing::ExpectInputError([&] { ReadPointCloud((dir / "a.xyz").string()); }, {"a.xyz", "cannot open"});
}

// ---- shared data ------------------------------------------------------------

TEST(PointsIoSharedDataTest, ScansFromManifest) {
  ARCS_REQUIRE_SHARED_DATA();
  const std::string pcd = testing::SharedData("scans/pcl_bunny_small/bun0.pcd");
  PointReadReport rep;
  const PointCloud bun = ReadPointCloud(pcd, &rep);
  EXPECT_EQ(bun.Size(), 397);
  EXPECT_TRUE(bun.HasNormals());
  EXPECT_TRUE(rep.skipped_lines.empty());
  const PointCloud kitten = ReadPointCloud(testing::SharedData("scans/cgal_points/kitten.xyz"));
  EXPECT_EQ(kitten.Size(), 5210);
  EXPECT_TRUE(kitten.HasNormals());
  // Normals of the kitten are unit length as stored.
  EXPECT_NEAR(kitten.N.rowwise().norm().minCoeff(), 1.0, 1e-3);

  // Every small point file of the manifest: count and normals as listed.
  std::ifstream f(testing::SharedData("scans/MANIFEST.tsv"));
  std::string line;
  std::getline(f, line);
  std::vector<std::string> cols;
  {
    std::stringstream ss(line);
    std::string c;
    while (std::getline(ss, c, '\t')) cols.push_back(c);
  }
  int checked = 0;
  while (std::getline(f, line)) {
    std::stringstream ss(line);
    std::string c;
    std::map<std::string, std::string> row;
    for (std::size_t i = 0; std::getline(ss, c, '\t') && i < cols.size(); ++i) row[cols[i]] = c;
    const std::string file = row["file"];
    if (file.rfind("pcl_bunny_small/", 0) != 0 && file.rfind("cgal_points/", 0) != 0) continue;
    const PointCloud pc = ReadPointCloud(testing::SharedData("scans/" + file));
    EXPECT_EQ(pc.Size(), std::stoi(row["points"])) << file;
    EXPECT_EQ(pc.HasNormals(), row["has_normals"] == "True") << file;
    EXPECT_TRUE(pc.P.allFinite()) << file;
    ++checked;
  }
  EXPECT_GE(checked, 10);
}

}  // namespace
}  // namespace arcs
