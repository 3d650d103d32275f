#include "framework/io/npy.h"

#include "framework/io/io_util.h"

#include <climits>
#include <cstring>

namespace arcs {
namespace {

using namespace io_internal;

constexpr char kMagic[] = "\x93NUMPY";  // 6 bytes

struct Dtype {
  char order = '<';  // '<' little, '>' big, '|' not applicable
  char kind = 'f';   // f, i, u, b
  int size = 8;
};

// A minimal parser for the Python dict literal of the .npy header, e.g.
// "{'descr': '<f8', 'fortran_order': False, 'shape': (3, 4), }".
class HeaderParser {
 public:
  HeaderParser(const std::string& path, std::string_view s, std::size_t base)
      : path_(path), s_(s), base_(base) {}

  [[noreturn]] void Fail(const std::string& what) const {
    ThrowAtOffset(path_, base_ + i_, "bad .npy header: " + what);
  }
  void SkipWs() {
    while (i_ < s_.size() && (IsSpace(s_[i_]) || s_[i_] == '\n')) ++i_;
  }
  bool Peek(char c) {
    SkipWs();
    return i_ < s_.size() && s_[i_] == c;
  }
  void Expect(char c) {
    if (!Peek(c)) Fail(std::string("expected '") + c + "'");
    ++i_;
  }
  std::string String() {
    SkipWs();
    if (i_ >= s_.size() || (s_[i_] != '\'' && s_[i_] != '"')) Fail("expected a quoted string");
    const char q = s_[i_++];
    const std::size_t b = i_;
    while (i_ < s_.size() && s_[i_] != q) ++i_;
    if (i_ >= s_.size()) Fail("unterminated string");
    return std::string(s_.substr(b, i_++ - b));
  }
  bool Bool() {
    SkipWs();
    if (s_.substr(i_, 4) == "True") {
      i_ += 4;
      return true;
    }
    if (s_.substr(i_, 5) == "False") {
      i_ += 5;
      return false;
    }
    Fail("expected True or False");
  }
  std::vector<std::int64_t> Tuple() {
    Expect('(');
    std::vector<std::int64_t> out;
    while (!Peek(')')) {
      SkipWs();
      const std::size_t b = i_;
      while (i_ < s_.size() && s_[i_] >= '0' && s_[i_] <= '9') ++i_;
      std::int64_t v = 0;
      if (b == i_ || ParseInt64(s_.substr(b, i_ - b), &v) != NumStatus::kOk)
        Fail("expected a non-negative integer in the shape");
      if (i_ < s_.size() && s_[i_] == 'L') ++i_;  // Python 2 long
      out.push_back(v);
      if (Peek(',')) {
        ++i_;
      } else if (!Peek(')')) {
        Fail("expected ',' or ')' in the shape");
      }
    }
    ++i_;
    return out;
  }
  // Skips a value of a key we do not know (string, bool, tuple, number).
  void SkipValue() {
    SkipWs();
    if (i_ < s_.size() && (s_[i_] == '\'' || s_[i_] == '"')) {
      String();
      return;
    }
    int depth = 0;
    while (i_ < s_.size()) {
      const char c = s_[i_];
      if (c == '(' || c == '[' || c == '{') ++depth;
      if (c == ')' || c == ']' || c == '}') {
        if (depth == 0) return;
        --depth;
      }
      if (c == ',' && depth == 0) return;
      ++i_;
    }
  }
  std::size_t pos() const { return base_ + i_; }

 private:
  const std::string& path_;
  std::string_view s_;
  std::size_t base_;
  std::size_t i_ = 0;
};

Dtype ParseDtype(const std::string& path, std::size_t offset, const std::string& d) {
  Dtype t;
  const std::string supported =
      " (supported: f4 f8 i1 i2 i4 i8 u1 u2 u4 u8 b1, little or big endian)";
  if (d.size() < 3) ThrowAtOffset(path, offset, "unsupported dtype '" + d + "'" + supported);
  t.order = d[0];
  t.kind = d[1];
  std::int64_t size = 0;
  if ((t.order != '<' && t.order != '>' && t.order != '|' && t.order != '=') ||
      ParseInt64(std::string_view(d).substr(2), &size) != NumStatus::kOk)
    ThrowAtOffset(path, offset, "unsupported dtype '" + d + "'" + supported);
  if (t.order == '=') t.order = kHostLittle ? '<' : '>';
  t.size = static_cast<int>(size);
  const bool ok = (t.kind == 'f' && (size == 4 || size == 8)) ||
                  ((t.kind == 'i' || t.kind == 'u') &&
                   (size == 1 || size == 2 || size == 4 || size == 8)) ||
                  (t.kind == 'b' && size == 1);
  if (!ok) ThrowAtOffset(path, offset, "unsupported dtype '" + d + "'" + supported);
  return t;
}

double LoadValue(const char* p, const Dtype& t) {
  const bool le = t.order != '>';
  switch (t.kind) {
    case 'f': return t.size == 4 ? Load<float>(p, le) : Load<double>(p, le);
    case 'b': return *p != 0 ? 1.0 : 0.0;
    case 'i':
      switch (t.size) {
        case 1: return static_cast<std::int8_t>(*p);
        case 2: return Load<std::int16_t>(p, le);
        case 4: return Load<std::int32_t>(p, le);
        default: return static_cast<double>(Load<std::int64_t>(p, le));
      }
    default:
      switch (t.size) {
        case 1: return static_cast<std::uint8_t>(*p);
        case 2: return Load<std::uint16_t>(p, le);
        case 4: return Load<std::uint32_t>(p, le);
        default: return static_cast<double>(Load<std::uint64_t>(p, le));
      }
  }
}


template <class T>
std::string EncodeNpyImpl(const std::string& path, const T* data, const std::vector<std::int64_t>& shape,
                          const char* descr) {
  std::int64_t n = 1;
  for (std::int64_t d : shape) {
    if (d < 0) throw Error("cannot write '" + path + "': negative dimension in shape");
    n *= d;
  }
  std::string dict = std::string("{'descr': '") + descr +
                     "', 'fortran_order': False, 'shape': " + NpyShapeString(shape) + ", }";
  // Pad with spaces and a final '\n' so that the data starts on a 64-byte
  // boundary (what numpy does); version 2.0 when the header exceeds 64 KiB.
  std::size_t pre = 10;
  if (dict.size() + 1 + 64 > 65535) pre = 12;
  const std::size_t total = (pre + dict.size() + 1 + 63) / 64 * 64;
  dict.append(total - pre - dict.size() - 1, ' ');
  dict += '\n';
  std::string out(kMagic, 6);
  out += static_cast<char>(pre == 10 ? 1 : 2);
  out += static_cast<char>(0);
  if (pre == 10) {
    AppendLE<std::uint16_t>(&out, static_cast<std::uint16_t>(dict.size()));
  } else {
    AppendLE<std::uint32_t>(&out, static_cast<std::uint32_t>(dict.size()));
  }
  out += dict;
  out.reserve(out.size() + static_cast<std::size_t>(n) * sizeof(T));
  for (std::int64_t i = 0; i < n; ++i) AppendLE<T>(&out, data[i]);
  return out;
}

}  // namespace

NpyArray ReadNpy(const std::string& path) {
  const FileBytes file = ReadWholeFile(path);
  return ParseNpy(path, file.view());
}

NpyArray ParseNpy(const std::string& path, std::string_view bytes) {
  if (bytes.size() < 10 || std::memcmp(bytes.data(), kMagic, 6) != 0)
    ThrowAtOffset(path, 0, "bad magic: not a .npy file (expected \\x93NUMPY)");
  const int major = static_cast<unsigned char>(bytes[6]);
  const int minor = static_cast<unsigned char>(bytes[7]);
  std::size_t header_start = 0, header_len = 0;
  if (major == 1) {
    header_len = Load<std::uint16_t>(bytes.data() + 8, true);
    header_start = 10;
  } else if (major == 2 || major == 3) {
    if (bytes.size() < 12) ThrowAtOffset(path, 8, "file ends inside the .npy preamble");
    header_len = Load<std::uint32_t>(bytes.data() + 8, true);
    header_start = 12;
  } else {
    ThrowAtOffset(path, 6,
                  "unsupported .npy format version " + std::to_string(major) + "." +
                      std::to_string(minor) + " (supported: 1.0, 2.0, 3.0)");
  }
  if (header_len > bytes.size() - header_start)
    ThrowAtOffset(path, 8,
                  "header length " + std::to_string(header_len) + " runs past the end of file");
  const std::string_view header(bytes.data() + header_start, header_len);
  HeaderParser p(path, header, header_start);
  std::string descr;
  bool have_descr = false, have_order = false, have_shape = false, fortran = false;
  std::size_t descr_pos = header_start;
  NpyArray arr;
  p.Expect('{');
  while (!p.Peek('}')) {
    const std::string key = p.String();
    p.Expect(':');
    if (key == "descr") {
      if (!p.Peek('\'') && !p.Peek('"'))
        ThrowAtOffset(path, p.pos(), "unsupported dtype: structured arrays are not supported");
      descr_pos = p.pos();
      descr = p.String();
      have_descr = true;
    } else if (key == "fortran_order") {
      fortran = p.Bool();
      have_order = true;
    } else if (key == "shape") {
      arr.shape = p.Tuple();
      have_shape = true;
    } else {
      p.SkipValue();
    }
    if (p.Peek(',')) {
      p.Expect(',');
    } else if (!p.Peek('}')) {
      p.Fail("expected ',' or '}'");
    }
  }
  if (!have_descr || !have_order || !have_shape)
    ThrowAtOffset(path, header_start,
                  "bad .npy header: needs the keys 'descr', 'fortran_order' and 'shape'");
  const Dtype dt = ParseDtype(path, descr_pos, descr);

  // Element count, guarded against overflow and against the file size before
  // anything is allocated.
  const std::size_t data_start = header_start + header_len;
  const std::uint64_t avail = bytes.size() - data_start;
  std::uint64_t n = 1;
  bool zero = false;
  for (std::int64_t d : arr.shape) zero = zero || d == 0;
  if (!zero) {
    for (std::int64_t d : arr.shape) {
      if (static_cast<std::uint64_t>(d) > avail + 1 || n > (avail + 1) / static_cast<std::uint64_t>(d)) {
        n = UINT64_MAX;
        break;
      }
      n *= static_cast<std::uint64_t>(d);
    }
  } else {
    n = 0;
  }
  if (n == UINT64_MAX || n > avail / static_cast<std::uint64_t>(dt.size))
    ThrowAtOffset(path, data_start,
                  "data shorter than the shape says: shape " + NpyShapeString(arr.shape) + " of '" +
                      descr + "' needs " +
                      (n == UINT64_MAX ? std::string("more") : std::to_string(n * dt.size)) +
                      " bytes, the file has " + std::to_string(avail) + " after the header");
  arr.data.resize(static_cast<std::size_t>(n));
  const char* src = bytes.data() + data_start;
  if (!fortran || arr.shape.size() <= 1) {
    for (std::size_t i = 0; i < n; ++i) arr.data[i] = LoadValue(src + i * dt.size, dt);
    return arr;
  }
  // Fortran order (first index fastest): walk the C-order multi-index and
  // keep the matching Fortran offset up to date.
  const std::size_t nd = arr.shape.size();
  std::vector<std::uint64_t> fstride(nd);
  std::uint64_t s = 1;
  for (std::size_t k = 0; k < nd; ++k) {
    fstride[k] = s;
    s *= static_cast<std::uint64_t>(arr.shape[k]);
  }
  std::vector<std::int64_t> idx(nd, 0);
  std::uint64_t f = 0;
  for (std::size_t c = 0; c < n; ++c) {
    arr.data[c] = LoadValue(src + f * dt.size, dt);
    for (std::size_t k = nd; k-- > 0;) {
      if (++idx[k] < arr.shape[k]) {
        f += fstride[k];
        break;
      }
      f -= fstride[k] * static_cast<std::uint64_t>(idx[k] - 1);
      idx[k] = 0;
    }
  }
  return arr;
}

void WriteNpy(const std::string& path, const double* data, const std::vector<std::int64_t>& shape) {
  WriteWholeFile(path, EncodeNpyImpl<double>(path, data, shape, "<f8"));
}

void WriteNpy(const std::string& path, const float* data, const std::vector<std::int64_t>& shape) {
  WriteWholeFile(path, EncodeNpyImpl<float>(path, data, shape, "<f4"));
}

std::string EncodeNpy(const double* data, const std::vector<std::int64_t>& shape) {
  return EncodeNpyImpl<double>("(npy)", data, shape, "<f8");
}

std::string NpyShapeString(const std::vector<std::int64_t>& shape) {
  std::string s = "(";
  for (std::size_t i = 0; i < shape.size(); ++i) {
    if (i) s += ", ";
    s += std::to_string(shape[i]);
  }
  if (shape.size() == 1) s += ",";
  return s + ")";
}

}  // namespace arcs
