// LZF decompression (Marc Lehmann's liblzf format), as used by PCD files
// with "DATA binary_compressed" (PCL's pcl::lzfCompress).
//
// The stream is a sequence of runs, each introduced by a control byte c:
//   c < 32   a literal run: the next c + 1 bytes are copied;
//   c >= 32  a back reference: length L = c >> 5 (7 = read one more byte and
//            add it), offset D = ((c & 31) << 8) + next byte + 1; copy L + 2
//            bytes from D bytes back in the output (the ranges may overlap).
#pragma once

#include <cstddef>
#include <string>

namespace arcs {

// Decompresses `in` (n bytes) into exactly out_size bytes at `out`. Returns
// "" on success, else what is wrong and at which input offset (a truncated
// stream, a reference before the start, output longer or shorter than
// out_size).
std::string LzfDecompress(const unsigned char* in, std::size_t n, unsigned char* out, std::size_t out_size);

}  // namespace arcs
