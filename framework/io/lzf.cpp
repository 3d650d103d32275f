#include "framework/io/lzf.h"

namespace arcs {

std::string LzfDecompress(const unsigned char* in, std::size_t n, unsigned char* out, std::size_t out_size) {
  std::size_t ip = 0, op = 0;
  while (ip < n) {
    const std::size_t at = ip;
    const unsigned c = in[ip++];
    if (c < 32) {  // literal run of c + 1 bytes
      const std::size_t len = c + 1;
      if (ip + len > n) return "LZF literal run at offset " + std::to_string(at) + " runs past the end of the data";
      if (op + len > out_size) return "LZF data at offset " + std::to_string(at) + " decodes to more than " + std::to_string(out_size) + " bytes";
      for (std::size_t i = 0; i < len; ++i) out[op++] = in[ip++];
      continue;
    }
    std::size_t len = c >> 5;
    if (len == 7) {
      if (ip >= n) return "LZF back reference at offset " + std::to_string(at) + " is truncated";
      len += in[ip++];
    }
    if (ip >= n) return "LZF back reference at offset " + std::to_string(at) + " is truncated";
    const std::size_t dist = ((c & 31u) << 8) + in[ip++] + 1;
    len += 2;
    if (dist > op) return "LZF back reference at offset " + std::to_string(at) + " points before the start of the output";
    if (op + len > out_size) return "LZF data at offset " + std::to_string(at) + " decodes to more than " + std::to_string(out_size) + " bytes";
    for (std::size_t i = 0; i < len; ++i, ++op) out[op] = out[op - dist];  // byte by byte: overlap repeats
  }
  if (op != out_size) return "LZF data decodes to " + std::to_string(op) + " bytes, the header says " + std::to_string(out_size);
  return "";
}

}  // namespace arcs
