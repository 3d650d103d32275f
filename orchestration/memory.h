// Process memory figures (Linux /proc).
#pragma once

#include <cstdint>

namespace arcs {

// Peak resident set size of this process so far (VmHWM), bytes; 0 if unknown.
std::int64_t PeakRssBytes();
// Current resident set size (VmRSS), bytes; 0 if unknown.
std::int64_t CurrentRssBytes();
// Resets the peak to the current RSS (writes 5 to /proc/self/clear_refs);
// returns false where the kernel does not allow it.
bool ResetPeakRss();

}  // namespace arcs
