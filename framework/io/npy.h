// NumPy .npy arrays (format versions 1.0, 2.0, 3.0).
//
// Reading converts every supported dtype to double: '<f4' '<f8' '<i1' '<i2'
// '<i4' '<i8' '<u1' '<u2' '<u4' '<u8' '|b1' '|u1' '|i1' and their big-endian
// ('>') variants. 64-bit integers beyond 2^53 lose precision. Arrays stored
// with fortran_order True are converted to C order. Values are returned as
// stored (NaN stays NaN): callers with a meaning for the numbers check them.
// Errors are arcs::InputError "FILE: offset N: what" (bad magic, bad header,
// unsupported dtype, data shorter than the shape says).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace arcs {

struct NpyArray {
  std::vector<std::int64_t> shape;  // () for a scalar
  std::vector<double> data;         // C order (last index fastest)
  std::int64_t Size() const {
    std::int64_t n = 1;
    for (std::int64_t d : shape) n *= d;
    return n;
  }
  int Ndim() const { return static_cast<int>(shape.size()); }
};

NpyArray ReadNpy(const std::string& path);
// The same from bytes in memory (e.g. a member of an .npz archive); `path`
// names the source in errors.
NpyArray ParseNpy(const std::string& path, std::string_view bytes);

// Writes '<f8' (or '<f4' for the float overload), C order, format 1.0 (2.0
// when the header does not fit in 64 KiB). data holds prod(shape) values.
// Throws arcs::Error when the file cannot be written.
void WriteNpy(const std::string& path, const double* data, const std::vector<std::int64_t>& shape);
void WriteNpy(const std::string& path, const float* data, const std::vector<std::int64_t>& shape);

// The bytes of a '<f8' .npy file (what WriteNpy writes).
std::string EncodeNpy(const double* data, const std::vector<std::int64_t>& shape);

// A shape as numpy prints it: "(3,)", "(4, 5)".
std::string NpyShapeString(const std::vector<std::int64_t>& shape);

}  // namespace arcs
