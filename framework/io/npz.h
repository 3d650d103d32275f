// NumPy .npz archives (numpy.savez / savez_compressed): a zip file of .npy
// members. Reading accepts stored and deflated members (zlib), zip64 sizes
// and offsets; writing stores members uncompressed (what numpy.savez does).
// Errors are arcs::InputError "FILE: offset N: what", or "FILE: member
// 'x.npy': what" for a malformed member.
#pragma once

#include "framework/io/npy.h"

#include <string>
#include <utility>
#include <vector>

namespace arcs {

// Members in archive order, names without the ".npy" suffix.
std::vector<std::pair<std::string, NpyArray>> ReadNpz(const std::string& path);

struct NpzMember {
  std::string name;                 // without ".npy"
  std::vector<double> data;         // C order
  std::vector<std::int64_t> shape;
};
// Writes '<f8' members, stored (no compression). Throws arcs::Error when the
// file cannot be written.
void WriteNpz(const std::string& path, const std::vector<NpzMember>& members);

}  // namespace arcs
