// Internal helpers shared by the readers and writers of arcs_io: whole-file
// reads, line/token cursors with line numbers, strict number parsing with
// std::from_chars, shortest round-trip number formatting and endian-aware
// binary scalars. Not part of the public API (namespace io_internal).
//
// Error locations follow framework/error.h: text formats report
// "FILE:LINE: what", binary formats "FILE: offset N: what".
#pragma once

#include "framework/error.h"

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <string_view>
#include <utility>

namespace arcs::io_internal {

// ---- files -----------------------------------------------------------------

// A whole file in memory (uninitialised allocation + one read: no zero fill).
class FileBytes {
 public:
  FileBytes() = default;
  FileBytes(std::unique_ptr<char[]> data, std::size_t size) : data_(std::move(data)), size_(size) {}
  std::string_view view() const { return {data_.get(), size_}; }
  std::size_t size() const { return size_; }

 private:
  std::unique_ptr<char[]> data_;
  std::size_t size_ = 0;
};

// The whole file. Throws InputError(path, 0, "cannot open ...") when the file
// is missing, a directory or unreadable.
FileBytes ReadWholeFile(const std::string& path);

// Writes `bytes` to `path` through a temporary file in the same directory and
// a rename, so a reader never sees a half-written file. Throws arcs::Error
// naming the path when it cannot be written.
void WriteWholeFile(const std::string& path, std::string_view bytes);

// The file name's extension in lower case, with the dot (".obj"), or "".
std::string LowerExtension(const std::string& path);

// ---- errors ----------------------------------------------------------------

[[noreturn]] void ThrowAtLine(const std::string& file, long line, const std::string& what);
[[noreturn]] void ThrowAtOffset(const std::string& file, std::uint64_t offset,
                                const std::string& what);

// A token quoted for an error message: at most 40 characters, control and
// non-ASCII bytes escaped, so a binary file never floods a message.
std::string Quote(std::string_view token);

// ---- text ------------------------------------------------------------------

// Whitespace inside a line ('\n' separates lines and is handled by LineReader).
inline bool IsSpace(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

// Iterates over the lines of a text (without the '\n'; a trailing '\r' is kept
// and treated as whitespace by Tokenizer). Skips a UTF-8 byte-order mark.
class LineReader {
 public:
  explicit LineReader(std::string_view text, long first_line = 1);
  // The next line; false at the end of the text.
  bool Next(std::string_view* line) {
    if (pos_ >= text_.size()) return false;
    const char* start = text_.data() + pos_;
    const void* nl = std::memchr(start, '\n', text_.size() - pos_);
    const std::size_t len =
        nl ? static_cast<std::size_t>(static_cast<const char*>(nl) - start) : text_.size() - pos_;
    *line = std::string_view(start, len);
    pos_ += len + (nl ? 1 : 0);
    ++line_;
    return true;
  }
  // 1-based number of the line last returned by Next (0 before the first).
  long line() const { return line_; }
  // Byte offset of the first character not yet returned.
  std::size_t offset() const { return pos_; }

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  long line_ = 0;
};

// Whitespace-separated tokens of one line.
class Tokenizer {
 public:
  explicit Tokenizer(std::string_view s) : s_(s) {}
  bool Next(std::string_view* tok) {
    while (pos_ < s_.size() && IsSpace(s_[pos_])) ++pos_;
    if (pos_ >= s_.size()) return false;
    const std::size_t b = pos_;
    while (pos_ < s_.size() && !IsSpace(s_[pos_])) ++pos_;
    *tok = s_.substr(b, pos_ - b);
    return true;
  }
  // Number of tokens left (consumes nothing).
  int CountRemaining() const;

 private:
  std::string_view s_;
  std::size_t pos_ = 0;
};

// Tokens across lines (for formats whose records may span lines, e.g. ASCII
// PLY); tracks the line of the token last returned.
class TokenStream {
 public:
  TokenStream(std::string_view text, long first_line) : text_(text), line_(first_line) {}
  // At the end of the text, returns false and keeps line() at the last
  // token's line (so "unexpected end of file" names a real line).
  bool Next(std::string_view* tok) {
    const std::size_t n = text_.size();
    const long line_before = line_;
    while (pos_ < n) {
      const char c = text_[pos_];
      if (c == '\n') {
        ++line_;
      } else if (!IsSpace(c)) {
        break;
      }
      ++pos_;
    }
    if (pos_ >= n) {
      line_ = line_before;
      return false;
    }
    const std::size_t b = pos_;
    while (pos_ < n && text_[pos_] != '\n' && !IsSpace(text_[pos_])) ++pos_;
    *tok = text_.substr(b, pos_ - b);
    return true;
  }
  long line() const { return line_; }
  std::size_t remaining() const { return text_.size() - pos_; }

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  long line_;
};

// The line part before a '#' comment.
inline std::string_view StripComment(std::string_view line) {
  const std::size_t h = line.find('#');
  return h == std::string_view::npos ? line : line.substr(0, h);
}
inline bool IsBlank(std::string_view line) {
  for (char c : line) {
    if (!IsSpace(c)) return false;
  }
  return true;
}

// 1-based line number of byte `pos` in `text`.
long LineOfOffset(std::string_view text, std::size_t pos);

// Throws InputError at the line of the first NUL byte: a text reader handed a
// binary file fails with a clear message instead of parsing garbage.
void CheckIsText(const std::string& file, std::string_view text, const char* format_name);

bool EqualsIgnoreCase(std::string_view a, std::string_view b);

// ---- numbers ---------------------------------------------------------------

enum class NumStatus { kOk, kBad, kOutOfRange };

// The whole token as a double (leading '+' allowed, "nan"/"inf" accepted and
// returned as such: callers decide whether non-finite values are errors).
NumStatus ParseDouble(std::string_view tok, double* out);

// The whole token as a signed 64-bit integer (leading '+' allowed).
NumStatus ParseInt64(std::string_view tok, std::int64_t* out);

// A coordinate: a decimal number, or an exact rational "p/q" of two integers
// (written by exact-arithmetic tools such as CGAL/wildmeshing). For
// |p|, |q| <= 2^53 the result is the correctly rounded double of p/q.
// *rational is set when the p/q form was used.
NumStatus ParseCoordinate(std::string_view tok, double* out, bool* rational);

// Shortest decimal that round-trips exactly (std::to_chars).
void AppendDouble(std::string* out, double v);
void AppendInt(std::string* out, std::int64_t v);
std::string FormatDouble(double v);

// ---- binary ----------------------------------------------------------------

inline constexpr bool kHostLittle = std::endian::native == std::endian::little;

template <class T>
inline T ByteSwap(T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
  std::memcpy(&v, b, sizeof(T));
  return v;
}

// Loads a T stored with the given byte order at p (unaligned).
template <class T>
inline T Load(const char* p, bool little_endian) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  if (little_endian != kHostLittle) v = ByteSwap(v);
  return v;
}

// Appends a T in little-endian byte order.
template <class T>
inline void AppendLE(std::string* out, T v) {
  if (!kHostLittle) v = ByteSwap(v);
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  out->append(b, sizeof(T));
}

}  // namespace arcs::io_internal
