// Redirects file descriptor 1 to /dev/null while alive: the Poisson back-ends
// (PCL's, and PoissonRecon inside Open3D at Debug verbosity) print with printf,
// and arcs' stdout carries results.
#pragma once

#include <cstdio>

#include <fcntl.h>
#include <unistd.h>

namespace arcs {

class StdoutSilencer {
 public:
  StdoutSilencer() {
    std::fflush(stdout);
    saved_ = ::dup(1);
    const int null = ::open("/dev/null", O_WRONLY);
    if (saved_ >= 0 && null >= 0) ::dup2(null, 1);
    if (null >= 0) ::close(null);
  }
  ~StdoutSilencer() {
    std::fflush(stdout);
    if (saved_ >= 0) {
      ::dup2(saved_, 1);
      ::close(saved_);
    }
  }
  StdoutSilencer(const StdoutSilencer&) = delete;
  StdoutSilencer& operator=(const StdoutSilencer&) = delete;

 private:
  int saved_ = -1;
};

}  // namespace arcs
