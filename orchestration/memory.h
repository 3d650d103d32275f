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

// Asks the allocator (glibc malloc) to keep freed memory in the process for
// reuse rather than hand it back to the kernel at once: blocks up to 1 GiB
// come from the heap instead of their own mappings, and the heap's free top
// is kept up to 1 GiB. RFTA's screened-Poisson solves and extractions
// allocate and free tens of MB per call, and with glibc's defaults every call
// faulted those pages in again (bunny_fixed n = 20, paper preset: 206k-275k
// minor page faults against 41k-46k, RFTA 20.0-20.4 s against 14.4-17.1 s;
// docs/rfta_table1.md, session 20). A process-wide setting: the arcs command
// and rfta_bench call it first thing; the Python module does not on import (it
// would change the interpreter's own allocations): arcs.keep_freed_memory() is opt-in. Returns false where the
// allocator refused or is not glibc's.
bool KeepFreedMemory();

}  // namespace arcs
