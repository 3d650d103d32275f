// Helpers shared by the tests.
#pragma once

#include "framework/error.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <unistd.h>
#include <fstream>
#include <string>
#include <vector>

namespace arcs::testing {

// The workplace's shared directory (../shared beside the checkout), or an
// override from the ARCS_SHARED_DIR environment variable. Empty if absent.
inline std::string SharedDir() {
  if (const char* env = std::getenv("ARCS_SHARED_DIR")) {
    if (std::filesystem::is_directory(env)) return env;
  }
  if (std::filesystem::is_directory(ARCS_SHARED_DIR "/data")) return ARCS_SHARED_DIR;
  return "";
}

inline std::string SharedData(const std::string& rel) { return SharedDir() + "/data/" + rel; }

// The directories TempDir made in this process, removed when the test
// program ends if every test passed (kept, and named on stderr, if one failed
// or ARCS_KEEP_TEST_DIRS is set). Only the process that made them removes
// them: a forked child that exits normally must not delete its parent's.
class TempDirRegistry {
 public:
  void Add(const std::filesystem::path& dir) { dirs_.push_back(dir); }
  ~TempDirRegistry() {
    if (::getpid() != owner_ || dirs_.empty()) return;
    const auto* unit = ::testing::UnitTest::GetInstance();
    if (std::getenv("ARCS_KEEP_TEST_DIRS") != nullptr || (unit != nullptr && !unit->Passed())) {
      std::fprintf(stderr, "test directories kept (%zu), e.g. %s\n", dirs_.size(), dirs_.front().c_str());
      return;
    }
    for (const auto& d : dirs_) {
      std::error_code ec;
      std::filesystem::remove_all(d, ec);
    }
  }

 private:
  pid_t owner_ = ::getpid();
  std::vector<std::filesystem::path> dirs_;
};

inline TempDirRegistry& TempDirs() {
  static TempDirRegistry registry;
  return registry;
}

// A fresh, empty temporary directory for one test, removed at the end of the
// test program (TempDirRegistry). The process id in the name keeps
// concurrent test runs (two checkouts, ctest -j) apart.
inline std::filesystem::path TempDir(const std::string& name) {
  auto dir = std::filesystem::temp_directory_path() / ("arcs_test_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  TempDirs().Add(dir);
  return dir;
}

// Writes `bytes` to `p` (binary).
inline void WriteFile(const std::filesystem::path& p, const std::string& bytes) {
  std::ofstream f(p, std::ios::binary);
  f << bytes;
}

// Runs f, expecting an arcs::InputError whose message contains every string
// in `parts`.
template <class F>
void ExpectInputError(F&& f, const std::vector<std::string>& parts) {
  try {
    f();
    ADD_FAILURE() << "no exception";
  } catch (const InputError& e) {
    for (const auto& p : parts) EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "wrong exception type: " << e.what();
  }
}

}  // namespace arcs::testing

// Skips the current test with a clear message when ../shared is not present.
#define ARCS_REQUIRE_SHARED_DATA()                                                   \
  do {                                                                               \
    if (::arcs::testing::SharedDir().empty())                                        \
      GTEST_SKIP() << "shared data not found (../shared/data or $ARCS_SHARED_DIR); " \
                      "this test needs the workplace's meshes";                      \
  } while (0)
