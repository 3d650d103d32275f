// .npz archives, LZF decoding, compressed PCD, and SDF files by extension.
#include "framework/io/lzf.h"
#include "framework/io/npz.h"
#include "framework/io/points_io.h"
#include "framework/io/sdf_io.h"

#include "tests/test_util.h"

#include <cstring>

namespace arcs {
namespace {

TEST(Lzf, LiteralsAndOverlappingBackReferences) {
  // "abc" as a literal run, then a back reference: ctrl 0x60 = length field 3
  // -> 5 bytes, distance (0 << 8) + 2 + 1 = 3 -> "abcab" (the copy overlaps
  // its own output, repeating the pattern).
  const unsigned char in[] = {0x02, 'a', 'b', 'c', 0x60, 0x02};
  unsigned char out[8] = {};
  ASSERT_EQ(LzfDecompress(in, sizeof in, out, 8), "");
  EXPECT_EQ(std::string(reinterpret_cast<char*>(out), 8), "abcabcab");
  // Long back reference: length field 7 + extra byte 10 -> 7 + 10 + 2 = 19, distance 1.
  const unsigned char in2[] = {0x00, 'x', 0xE0, 10, 0x00};
  unsigned char out2[20] = {};
  ASSERT_EQ(LzfDecompress(in2, sizeof in2, out2, 20), "");
  EXPECT_EQ(std::string(reinterpret_cast<char*>(out2), 20), std::string(20, 'x'));
}

TEST(Lzf, Errors) {
  unsigned char out[16] = {};
  const unsigned char truncated[] = {0x05, 'a', 'b'};
  EXPECT_NE(LzfDecompress(truncated, sizeof truncated, out, 6).find("runs past the end"), std::string::npos);
  const unsigned char before_start[] = {0x00, 'a', 0x20, 0x05};
  EXPECT_NE(LzfDecompress(before_start, sizeof before_start, out, 4).find("before the start"), std::string::npos);
  const unsigned char ok[] = {0x02, 'a', 'b', 'c'};
  EXPECT_NE(LzfDecompress(ok, sizeof ok, out, 5).find("decodes to 3 bytes, the header says 5"), std::string::npos);
  EXPECT_NE(LzfDecompress(ok, sizeof ok, out, 2).find("more than 2 bytes"), std::string::npos);
}

// A binary_compressed PCD as PCL writes it: fields one after another (all x,
// then all y, ...), LZF-coded; here as literal runs plus one back reference.
TEST(Pcd, BinaryCompressedFieldsOfAllPoints) {
  const int n = 4;
  float xyz[3][n] = {{0, 1, 2, 3}, {10, 11, 12, 13}, {-1, -1, -1, -1}};
  std::string soa;
  for (auto& f : xyz) soa.append(reinterpret_cast<const char*>(f), sizeof f);
  // LZF: the x and y fields (32 bytes) as one literal run, then the z field
  // (16 bytes, one float repeated) as a 4-byte literal and a 12-byte back
  // reference at distance 4: ctrl = ((12 - 2) = 7 + 3 extra) << 5 | high bits.
  std::string lzf;
  lzf += static_cast<char>(31);
  lzf += soa.substr(0, 32);
  lzf += static_cast<char>(3);
  lzf += soa.substr(32, 4);
  lzf += static_cast<char>(0xE0);
  lzf += static_cast<char>(3);
  lzf += static_cast<char>(3);
  const std::string header =
      "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 4\nHEIGHT 1\n"
      "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 4\nDATA binary_compressed\n";
  std::string sizes(8, '\0');
  const std::uint32_t cs = static_cast<std::uint32_t>(lzf.size()), us = static_cast<std::uint32_t>(soa.size());
  std::memcpy(sizes.data(), &cs, 4);
  std::memcpy(sizes.data() + 4, &us, 4);
  const auto dir = testing::TempDir("pcd_compressed");
  const std::string p = (dir / "c.pcd").string();
  testing::WriteFile(p, header + sizes + lzf);
  const PointCloud pc = ReadPointCloud(p);
  ASSERT_EQ(pc.Size(), n);
  EXPECT_FALSE(pc.HasNormals());
  for (int i = 0; i < n; ++i) {
    EXPECT_EQ(pc.P(i, 0), i);
    EXPECT_EQ(pc.P(i, 1), 10 + i);
    EXPECT_EQ(pc.P(i, 2), -1);
  }
  // A size header that disagrees with POINTS x record size, and corrupt data.
  std::string wrong = sizes;
  const std::uint32_t us2 = us + 4;
  std::memcpy(wrong.data() + 4, &us2, 4);
  testing::WriteFile(p, header + wrong + lzf);
  testing::ExpectInputError([&] { ReadPointCloud(p); }, {p + ": offset", "decodes to 52 bytes", "need 48"});
  std::string cut = sizes;
  const std::uint32_t cs2 = cs - 1;
  std::memcpy(cut.data(), &cs2, 4);
  testing::WriteFile(p, header + cut + lzf.substr(0, lzf.size() - 1));
  testing::ExpectInputError([&] { ReadPointCloud(p); }, {p + ": offset", "LZF"});
}

// The same layout from PCL's own encoder: pcl::io::savePCDFileBinaryCompressed
// (PCL 1.13) of 24 PointXYZ (0.5 i, 0.25 (i mod 4), -1), bytes as written.
TEST(Pcd, BinaryCompressedWrittenByPcl) {
  const std::string header =
      "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\n"
      "COUNT 1 1 1\nWIDTH 24\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 24\nDATA binary_compressed\n";
  const std::string body(
      "\x7d\x00\x00\x00\x20\x01\x00\x00\x01\x00\x00\x60\x00\x03\x3f\x00\x00\x80\x20\x03\x00\xc0\x20\x03"
      "\x04\x00\x40\x00\x00\x20\x20\x03\x00\x40\x20\x03\x00\x60\x20\x03\x00\x80\x20\x03\x00\x90\x20\x03"
      "\x00\xa0\x20\x03\x00\xb0\x20\x03\x00\xc0\x20\x03\x00\xd0\x20\x03\x00\xe0\x20\x03\x00\xf0\x20\x03"
      "\x04\x00\x41\x00\x00\x08\x20\x03\x00\x10\x20\x03\x00\x18\x20\x03\x00\x20\x20\x03\x00\x28\x20\x03"
      "\x00\x30\x20\x03\x00\x38\x20\x03\x40\x00\x01\x80\x3e\x20\x05\x20\x5b\x00\x40\x20\x03\x40\x00\xe0"
      "\x43\x0f\x01\x80\xbf\x20\xbb\xe0\x4e\x03\x01\x80\xbf",
      133);
  const auto dir = testing::TempDir("pcd_pcl_compressed");
  const std::string p = (dir / "pcl.pcd").string();
  testing::WriteFile(p, header + body);
  const PointCloud pc = ReadPointCloud(p);
  ASSERT_EQ(pc.Size(), 24);
  for (int i = 0; i < 24; ++i) {
    EXPECT_EQ(pc.P(i, 0), 0.5 * i);
    EXPECT_EQ(pc.P(i, 1), 0.25 * (i % 4));
    EXPECT_EQ(pc.P(i, 2), -1.0);
  }
}

TEST(Npz, RoundTripAndErrors) {
  const auto dir = testing::TempDir("npz");
  const std::string p = (dir / "a.npz").string();
  std::vector<NpzMember> m(2);
  m[0] = {"U", {1, 2, 3, 4, 5, 6}, {2, 3}};
  m[1] = {"S", {0.5, -0.25}, {2}};
  WriteNpz(p, m);
  const auto r = ReadNpz(p);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[0].first, "U");
  EXPECT_EQ(r[0].second.shape, (std::vector<std::int64_t>{2, 3}));
  EXPECT_EQ(r[0].second.data, m[0].data);
  EXPECT_EQ(r[1].first, "S");
  EXPECT_EQ(r[1].second.data, m[1].data);
  testing::WriteFile(p, "PK\x03\x04 not really a zip file at all........");
  testing::ExpectInputError([&] { ReadNpz(p); }, {p, "end-of-central-directory"});
  testing::WriteFile(p, "\x93NUMPY");
  testing::ExpectInputError([&] { ReadNpz(p); }, {p, "not an .npz"});
}

SdfSamples Scattered() {
  SdfSamples s;
  s.points.resize(3, 3);
  s.points << 0.1, 0.2, 0.3, -1, 0, 1, 1e-300, 2.5, -0.75;
  s.values.resize(3);
  s.values << 0.25, -1.0 / 3.0, 7;
  return s;
}

TEST(SdfFiles, EveryWrittenFormatReadsBackExactly) {
  const auto dir = testing::TempDir("sdf_formats");
  const SdfSamples s = Scattered();
  for (const char* ext : {".npy", ".npz", ".txt", ".xyzs", ".sdf"}) {
    const std::string p = (dir / (std::string("s") + ext)).string();
    WriteSdf(p, s);
    const SdfSamples r = ReadSdf(p);
    EXPECT_FALSE(r.grid) << ext;
    EXPECT_EQ(r.points, s.points) << ext;
    EXPECT_EQ(r.values, s.values) << ext;
  }
  // Grids: .npy (+ .bounds) and .npz (S, bounds) keep the layout and bounds.
  NpyArray a;
  a.shape = {2, 3, 4};
  for (int i = 0; i < 24; ++i) a.data.push_back(i * 0.5 - 3);
  const SdfSamples g = SdfGridFromArray("g", a, {0, -1, 2}, {1, 1, 5});
  for (const char* ext : {".npy", ".npz"}) {
    const std::string p = (dir / (std::string("g") + ext)).string();
    WriteSdf(p, g);
    const SdfSamples r = ReadSdf(p);
    ASSERT_TRUE(r.grid) << ext;
    EXPECT_EQ(r.grid->dims, g.grid->dims);
    EXPECT_EQ(r.grid->min, g.grid->min);
    EXPECT_EQ(r.grid->max, g.grid->max);
    EXPECT_EQ(r.values, g.values) << ext;
    EXPECT_EQ(r.points, g.points) << ext;
  }
  // A scattered .npy over a stale grid sidecar still reads as samples.
  WriteSdf((dir / "g.npy").string(), s);
  EXPECT_FALSE(ReadSdf((dir / "g.npy").string()).grid);
  testing::ExpectInputError([&] { WriteSdf((dir / "s.xyz").string(), s); }, {"s.xyz", "unsupported SDF output extension '.xyz'", ".npz"});
  testing::ExpectInputError([&] { ReadSdf((dir / "s.csv").string()); }, {"unsupported SDF file extension '.csv'"});
}

}  // namespace
}  // namespace arcs
