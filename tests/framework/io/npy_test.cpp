#include "framework/io/npy.h"

#include "framework/error.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <bit>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>

namespace arcs {
namespace {

namespace fs = std::filesystem;

using testing::WriteFile;

std::string ReadFile(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), {});
}

template <class T>
void Put(std::string* s, T v, bool big) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if (big == (std::endian::native == std::endian::little)) {
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
  }
  s->append(b, sizeof(T));
}

// A .npy file by hand: magic, version, header length, dict, data.
std::string Npy(int major, const std::string& dict, const std::string& data) {
  std::string h = dict + "\n";
  std::string s = "\x93NUMPY";
  s += static_cast<char>(major);
  s += '\0';
  if (major == 1) {
    Put<std::uint16_t>(&s, static_cast<std::uint16_t>(h.size()), false);
  } else {
    Put<std::uint32_t>(&s, static_cast<std::uint32_t>(h.size()), false);
  }
  return s + h + data;
}

template <class F>
void ExpectOffsetError(F&& f, const std::string& file, long offset, const std::string& what) {
  try {
    f();
    ADD_FAILURE() << "no exception; expected " << what;
  } catch (const InputError& e) {
    const std::string msg = e.what();
    if (offset >= 0) {
      EXPECT_NE(msg.find(file + ": offset " + std::to_string(offset) + ": "), std::string::npos)
          << msg;
    } else {
      EXPECT_NE(msg.find(file + ": offset "), std::string::npos) << msg;
    }
    EXPECT_NE(msg.find(what), std::string::npos) << msg;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "wrong exception type: " << e.what();
  }
}

TEST(NpyTest, WriteReadRoundTripIsExact) {
  const auto dir = testing::TempDir("npy_roundtrip");
  const std::vector<std::vector<std::int64_t>> shapes = {{}, {0}, {5}, {2, 3, 4}, {3, 0, 2}};
  for (const auto& shape : shapes) {
    std::int64_t n = 1;
    for (auto d : shape) n *= d;
    std::vector<double> data(static_cast<std::size_t>(n));
    for (std::int64_t i = 0; i < n; ++i) data[i] = std::sin(1.0 + i) * std::pow(10.0, i % 7 - 3);
    const std::string path = (dir / "a.npy").string();
    WriteNpy(path, data.data(), shape);
    // numpy's layout: 64-byte aligned data start, newline-terminated header.
    const std::string raw = ReadFile(path);
    const std::size_t hl = static_cast<unsigned char>(raw[8]) | (static_cast<unsigned char>(raw[9]) << 8);
    EXPECT_EQ((10 + hl) % 64, 0u);
    EXPECT_EQ(raw[10 + hl - 1], '\n');
    const NpyArray a = ReadNpy(path);
    EXPECT_EQ(a.shape, shape);
    EXPECT_EQ(a.data, data);
  }
  const std::vector<float> f = {1.5f, -2.25f, 3.1f};
  const std::string fp = (dir / "f.npy").string();
  WriteNpy(fp, f.data(), {3});
  const NpyArray a = ReadNpy(fp);
  ASSERT_EQ(a.data.size(), 3u);
  EXPECT_EQ(a.data[2], static_cast<double>(3.1f));
  EXPECT_NE(ReadFile(fp).find("'<f4'"), std::string::npos);
}

TEST(NpyTest, AllDtypesBothEndiannesses) {
  const auto dir = testing::TempDir("npy_dtypes");
  const std::string shape = "'fortran_order': False, 'shape': (3,), }";
  for (bool big : {false, true}) {
    const char o = big ? '>' : '<';
    struct Case {
      std::string descr;
      std::string data;
      std::vector<double> expect;
    };
    std::vector<Case> cases;
    {
      std::string d;
      for (float v : {0.5f, -1.0f, 1e30f}) Put(&d, v, big);
      cases.push_back({std::string(1, o) + "f4", d, {0.5, -1.0, static_cast<double>(1e30f)}});
    }
    {
      std::string d;
      for (double v : {0.1, -1e300, 3.0}) Put(&d, v, big);
      cases.push_back({std::string(1, o) + "f8", d, {0.1, -1e300, 3.0}});
    }
    {
      std::string d;
      for (std::int32_t v : {-5, 0, 2147483647}) Put(&d, v, big);
      cases.push_back({std::string(1, o) + "i4", d, {-5, 0, 2147483647}});
    }
    {
      std::string d;
      for (std::int64_t v : {std::int64_t{-7}, std::int64_t{1} << 40, std::int64_t{9}}) Put(&d, v, big);
      cases.push_back({std::string(1, o) + "i8", d, {-7, std::ldexp(1.0, 40), 9}});
    }
    {
      std::string d;
      for (std::uint16_t v : {1, 65535, 7}) Put(&d, v, big);
      cases.push_back({std::string(1, o) + "u2", d, {1, 65535, 7}});
    }
    cases.push_back({"|u1", std::string("\x00\xff\x07", 3), {0, 255, 7}});
    cases.push_back({"|b1", std::string("\x00\x01\x01", 3), {0, 1, 1}});
    cases.push_back({"|i1", std::string("\xff\x80\x07", 3), {-1, -128, 7}});
    for (const Case& c : cases) {
      const std::string path = (dir / "d.npy").string();
      WriteFile(path, Npy(1, "{'descr': '" + c.descr + "', " + shape, c.data));
      const NpyArray a = ReadNpy(path);
      EXPECT_EQ(a.shape, std::vector<std::int64_t>{3}) << c.descr;
      EXPECT_EQ(a.data, c.expect) << c.descr;
    }
  }
}

TEST(NpyTest, FortranOrderIsConvertedToCOrder) {
  const auto dir = testing::TempDir("npy_fortran");
  // a[i, j, k] = 100 i + 10 j + k, shape (2, 3, 4), stored first index fastest.
  std::string d;
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 2; ++i) Put<double>(&d, 100 * i + 10 * j + k, false);
  const std::string path = (dir / "f.npy").string();
  WriteFile(path, Npy(1, "{'descr': '<f8', 'fortran_order': True, 'shape': (2, 3, 4), }", d));
  const NpyArray a = ReadNpy(path);
  ASSERT_EQ(a.shape, (std::vector<std::int64_t>{2, 3, 4}));
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 4; ++k) EXPECT_EQ(a.data[(i * 3 + j) * 4 + k], 100 * i + 10 * j + k);
  // 2D, big-endian ints, Python-2 style long dims.
  std::string e;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 2; ++i) Put<std::int32_t>(&e, 10 * i + j, true);
  WriteFile(path, Npy(1, "{'descr': '>i4', 'fortran_order': True, 'shape': (2L, 3L), }", e));
  const NpyArray b = ReadNpy(path);
  EXPECT_EQ(b.data, (std::vector<double>{0, 1, 2, 10, 11, 12}));
}

TEST(NpyTest, Versions2And3) {
  const auto dir = testing::TempDir("npy_versions");
  std::string d;
  Put<double>(&d, 2.5, false);
  Put<double>(&d, -1.0, false);
  for (int v : {2, 3}) {
    const std::string path = (dir / ("v" + std::to_string(v) + ".npy")).string();
    WriteFile(path, Npy(v, "{\"descr\": \"<f8\", \"shape\": (1, 2), \"fortran_order\": False}", d));
    const NpyArray a = ReadNpy(path);
    EXPECT_EQ(a.shape, (std::vector<std::int64_t>{1, 2}));
    EXPECT_EQ(a.data, (std::vector<double>{2.5, -1.0}));
  }
}

TEST(NpyTest, MalformedFilesThrowWithOffsets) {
  const auto dir = testing::TempDir("npy_bad");
  const std::string ok = "{'descr': '<f8', 'fortran_order': False, 'shape': (2,), }";
  std::string two;
  Put<double>(&two, 1.0, false);
  Put<double>(&two, 2.0, false);
  struct Case {
    std::string bytes;
    long offset;
    std::string what;
  };
  std::string bad_version = Npy(1, ok, two);
  bad_version[6] = 9;
  std::string long_header = Npy(1, ok, two);
  long_header[8] = '\xff';
  long_header[9] = '\x7f';
  const std::vector<Case> cases = {
      {"PK\x03\x04 a zip file, not npy", 0, "bad magic"},
      {"\x93NUM", 0, "bad magic"},
      {bad_version, 6, "unsupported .npy format version 9.0"},
      {long_header, 8, "runs past the end"},
      {Npy(1, "{'descr': '<f8', 'shape': (2,), }", two), 10, "needs the keys"},
      {Npy(1, "{'descr': '<f8' 'fortran_order': False, 'shape': (2,), }", two), -1,
       "bad .npy header"},
      {Npy(1, "{'descr': '<f8', 'fortran_order': Maybe, 'shape': (2,), }", two), -1,
       "True or False"},
      {Npy(1, "{'descr': '<f8', 'fortran_order': False, 'shape': (2, -1), }", two), -1,
       "non-negative integer"},
      {Npy(1, "{'descr': '<c16', 'fortran_order': False, 'shape': (1,), }", two), 20,
       "unsupported dtype '<c16'"},
      {Npy(1, "{'descr': '<U8', 'fortran_order': False, 'shape': (1,), }", two), -1,
       "unsupported dtype"},
      {Npy(1, "{'descr': [('a', '<f4')], 'fortran_order': False, 'shape': (1,), }", two), -1,
       "structured"},
      {Npy(1, "{'descr': '<f8', 'fortran_order': False, 'shape': (3,), }", two), -1,
       "data shorter than the shape says"},
      {Npy(1, "{'descr': '<f8', 'fortran_order': False, 'shape': (1000000, 1000000, 1000000, "
              "1000000), }",
           two),
       -1, "data shorter than the shape says"},
  };
  const auto t0 = std::chrono::steady_clock::now();
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const std::string path = (dir / ("bad" + std::to_string(i) + ".npy")).string();
    WriteFile(path, cases[i].bytes);
    ExpectOffsetError([&] { ReadNpy(path); }, path, cases[i].offset, cases[i].what);
  }
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 1.0);
  try {
    ReadNpy((dir / "missing.npy").string());
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot open"), std::string::npos);
  }
  const double x = 1;
  EXPECT_THROW(WriteNpy((dir / "nodir" / "x.npy").string(), &x, {1}), Error);
}

}  // namespace
}  // namespace arcs
