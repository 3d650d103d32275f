#include "orchestration/memory.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace arcs {

namespace {
std::int64_t ReadStatusKb(const char* key) {
  FILE* f = std::fopen("/proc/self/status", "r");
  if (!f) return 0;
  char line[256];
  std::int64_t kb = 0;
  const size_t n = std::strlen(key);
  while (std::fgets(line, sizeof line, f)) {
    if (std::strncmp(line, key, n) == 0) {
      kb = std::atoll(line + n);
      break;
    }
  }
  std::fclose(f);
  return kb * 1024;
}
}  // namespace

std::int64_t PeakRssBytes() { return ReadStatusKb("VmHWM:"); }
std::int64_t CurrentRssBytes() { return ReadStatusKb("VmRSS:"); }

bool ResetPeakRss() {
  FILE* f = std::fopen("/proc/self/clear_refs", "w");
  if (!f) return false;
  const bool ok = std::fputs("5", f) >= 0;
  return std::fclose(f) == 0 && ok;
}

bool KeepFreedMemory() {
#if defined(__GLIBC__)
  constexpr int kLimit = 1 << 30;
  const bool mmap_ok = mallopt(M_MMAP_THRESHOLD, kLimit) == 1;
  const bool trim_ok = mallopt(M_TRIM_THRESHOLD, kLimit) == 1;
  return mmap_ok && trim_ok;
#else
  return false;
#endif
}

}  // namespace arcs
