// A deterministic mutation fuzzer for the test suite: fixed seeds, small
// seed files, each mutant run in a forked child with a short timeout. The
// child exits 0 when the code under test succeeded or threw arcs::Error (a
// clear error), 2 for any other exception; a crash, an ASan/UBSan finding
// (their exit code / abort) or a timeout (SIGALRM) shows in the status.
#pragma once

#include "framework/error.h"
#include "framework/util/rng.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#if defined(__SANITIZE_ADDRESS__)
#define ARCS_FUZZ_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define ARCS_FUZZ_ASAN 1
#endif
#endif

namespace arcs::testing {

// One mutation of `s` drawn from `rng`: flip / set / insert / delete bytes,
// duplicate or drop a range, cut the tail, or replace a number with a
// hostile one (huge, negative, subnormal, near-overflow, NaN).
inline std::string Mutate(const std::string& s, Rng& rng) {
  static const char* const kNumbers[] = {"999999999999999999", "1000000000000000000", "-1", "0",
                                         "4294967302", "1e-310", "1e308", "-1e308", "nan", "inf",
                                         "2147483648", "9223372036854775807", "18446744073709551615",
                                         "0x10", "1/0", "-0", "1e999", "3.5", "65536", "255"};
  std::string m = s;
  const auto pick = [&](std::size_t n) { return n == 0 ? std::size_t{0} : static_cast<std::size_t>(rng.UniformInt(n)); };
  const int rounds = 1 + static_cast<int>(pick(3));
  for (int r = 0; r < rounds; ++r) {
    const std::size_t n = m.size();
    switch (pick(9)) {
      case 0:  // flip a bit
        if (n) m[pick(n)] ^= static_cast<char>(1u << pick(8));
        break;
      case 1:  // set a byte (often a structural one)
        if (n) {
          static const char kBytes[] = {'\0', '\n', ' ', '-', '.', '/', '#', '9', '\xff', '\xef', ':', '&', '*', '[', '{'};
          m[pick(n)] = kBytes[pick(sizeof(kBytes))];
        }
        break;
      case 2:  // insert a byte
        m.insert(m.begin() + static_cast<std::ptrdiff_t>(pick(n + 1)), static_cast<char>(pick(256)));
        break;
      case 3:  // delete a range
        if (n) {
          const std::size_t a = pick(n);
          m.erase(a, 1 + pick(std::min<std::size_t>(16, n - a)));
        }
        break;
      case 4:  // duplicate a range
        if (n) {
          const std::size_t a = pick(n), len = 1 + pick(std::min<std::size_t>(64, n - a));
          m.insert(pick(n + 1), m.substr(a, len));
        }
        break;
      case 5:  // cut the tail
        m.resize(pick(n + 1));
        break;
      case 6:
      case 7: {  // replace a run of digits with a hostile number
        std::vector<std::size_t> starts;
        for (std::size_t i = 0; i < n; ++i)
          if (std::isdigit(static_cast<unsigned char>(m[i])) && (i == 0 || !std::isdigit(static_cast<unsigned char>(m[i - 1]))))
            starts.push_back(i);
        if (starts.empty()) break;
        const std::size_t a = starts[pick(starts.size())];
        std::size_t b = a;
        while (b < n && (std::isdigit(static_cast<unsigned char>(m[b])) || m[b] == '.' || m[b] == 'e')) ++b;
        m.replace(a, b - a, kNumbers[pick(sizeof(kNumbers) / sizeof(kNumbers[0]))]);
        break;
      }
      case 8:  // overwrite 4 or 8 bytes with a hostile binary integer
        if (n >= 8) {
          const std::uint64_t vals[] = {0xffffffffull, 0x7fffffffull, 0xffffffffffffffffull, 0x0de0b6b3a7640000ull,
                                        0x8000000000000000ull, 1ull, 0ull};
          const std::uint64_t v = vals[pick(7)];
          std::memcpy(&m[pick(n - 7)], &v, pick(2) ? 8 : 4);
        }
        break;
    }
  }
  return m;
}

// Runs `fn` in a forked child with `timeout_s`; "" when it succeeded or
// threw arcs::Error, otherwise what went wrong.
inline std::string RunIsolated(const std::function<void()>& fn, unsigned timeout_s) {
  std::fflush(nullptr);
  const pid_t pid = fork();
  if (pid < 0) return std::string("fork failed: ") + std::strerror(errno);
  if (pid == 0) {
    alarm(timeout_s);
#ifndef ARCS_FUZZ_ASAN
    // A mutant must not be able to take the machine's memory (ASan reserves
    // terabytes of address space, so no limit there).
    struct rlimit lim{};
    lim.rlim_cur = lim.rlim_max = 4ull << 30;
    setrlimit(RLIMIT_AS, &lim);
#endif
    int rc = 0;
    try {
      fn();
    } catch (const arcs::Error&) {
      rc = 0;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "fuzz: not an arcs::Error: %s\n", e.what());
      rc = 2;
    } catch (...) {
      rc = 2;
    }
    std::fflush(nullptr);
    _exit(rc);
  }
  int status = 0;
  if (waitpid(pid, &status, 0) != pid) return "waitpid failed";
  if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    return sig == SIGALRM ? "timeout (" + std::to_string(timeout_s) + " s)"
                          : "signal " + std::to_string(sig) + " (" + strsignal(sig) + ")";
  }
  if (WEXITSTATUS(status) == 2) return "an exception that is not arcs::Error";
  if (WEXITSTATUS(status) != 0) return "exit status " + std::to_string(WEXITSTATUS(status)) + " (a sanitizer finding?)";
  return "";
}

// Fuzzes `read` (which reads the file it is given) with `count` mutants of
// `seed_bytes` written to DIR/mutant<ext>; a failing mutant is kept as
// DIR/fail_<i><ext> and named in the failure message.
inline void FuzzReader(const std::string& name, const std::string& seed_bytes, const std::string& ext, int count,
                       std::uint64_t seed, const std::function<void(const std::string&)>& read,
                       unsigned timeout_s = 10) {
  namespace fs = std::filesystem;
  const fs::path dir = TempDir("fuzz_" + name);  // kept when a mutant fails (test_util.h)
  // The seed itself must read.
  {
    const std::string p = (dir / ("seed" + ext)).string();
    std::ofstream(p, std::ios::binary) << seed_bytes;
    EXPECT_EQ(RunIsolated([&] { read(p); }, timeout_s), "") << name << ": the seed file";
  }
  Rng rng(seed);
  int failures = 0;
  for (int i = 0; i < count; ++i) {
    const std::string m = Mutate(seed_bytes, rng);
    const std::string p = (dir / ("mutant" + ext)).string();
    {
      std::ofstream f(p, std::ios::binary | std::ios::trunc);
      f.write(m.data(), static_cast<std::streamsize>(m.size()));
    }
    const std::string why = RunIsolated([&] { read(p); }, timeout_s);
    if (!why.empty()) {
      const fs::path keep = dir / ("fail_" + std::to_string(i) + ext);
      fs::copy_file(p, keep, fs::copy_options::overwrite_existing);
      ADD_FAILURE() << name << " mutant " << i << " (seed " << seed << "): " << why << "; kept as " << keep;
      if (++failures >= 5) break;
    }
  }
  if (failures == 0) fs::remove_all(dir);
}

}  // namespace arcs::testing
