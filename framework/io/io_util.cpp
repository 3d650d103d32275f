#include "framework/io/io_util.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <system_error>

namespace arcs::io_internal {

namespace fs = std::filesystem;

FileBytes ReadWholeFile(const std::string& path) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec || !fs::exists(st)) throw InputError(path, 0, "cannot open: no such file");
  if (fs::is_directory(st)) throw InputError(path, 0, "cannot open: is a directory");
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw InputError(path, 0, std::string("cannot open: ") + std::strerror(errno));
  std::uintmax_t size = fs::is_regular_file(st) ? fs::file_size(path, ec) : 0;
  if (ec) size = 0;
  std::unique_ptr<char[]> data;
  std::size_t got = 0;
  bool failed = false;
  if (size > 0) {
    // Regular file: one allocation, one read.
    data.reset(new char[size]);
    got = std::fread(data.get(), 1, size, f);
    failed = got != size && std::ferror(f);
  } else {
    // Pipes and /proc files report size 0: read in chunks.
    std::string s;
    char chunk[1 << 16];
    std::size_t n;
    while ((n = std::fread(chunk, 1, sizeof(chunk), f)) > 0) s.append(chunk, n);
    failed = std::ferror(f) != 0;
    data.reset(new char[s.size() + 1]);
    std::memcpy(data.get(), s.data(), s.size());
    got = s.size();
  }
  std::fclose(f);
  if (failed) throw InputError(path, 0, "cannot open: read error");
  return FileBytes(std::move(data), got);
}

void WriteWholeFile(const std::string& path, std::string_view bytes) {
  const std::string tmp = path + ".arcs-tmp";
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) throw Error("cannot write '" + path + "': " + std::strerror(errno));
  const std::size_t put = std::fwrite(bytes.data(), 1, bytes.size(), f);
  const int err = errno;
  const bool close_failed = std::fclose(f) != 0;
  if (put != bytes.size() || close_failed) {
    std::remove(tmp.c_str());
    throw Error("cannot write '" + path + "': " + std::strerror(err ? err : EIO));
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    std::remove(tmp.c_str());
    throw Error("cannot write '" + path + "': " + ec.message());
  }
}

std::string LowerExtension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

void ThrowAtLine(const std::string& file, long line, const std::string& what) {
  throw InputError(file, line, what);
}

void ThrowAtOffset(const std::string& file, std::uint64_t offset, const std::string& what) {
  throw InputError(file, 0, "offset " + std::to_string(offset) + ": " + what);
}

std::string Quote(std::string_view token) {
  std::string out = "'";
  const std::size_t n = std::min<std::size_t>(token.size(), 40);
  for (std::size_t i = 0; i < n; ++i) {
    const unsigned char c = static_cast<unsigned char>(token[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      char buf[8];
      std::snprintf(buf, sizeof(buf), "\\x%02x", c);
      out += buf;
    }
  }
  if (token.size() > n) out += "...";
  out += "'";
  return out;
}

LineReader::LineReader(std::string_view text, long first_line)
    : text_(text), line_(first_line - 1) {
  if (first_line == 1 && text_.size() >= 3 && text_.substr(0, 3) == "\xEF\xBB\xBF") pos_ = 3;
}

int Tokenizer::CountRemaining() const {
  Tokenizer copy = *this;
  std::string_view t;
  int n = 0;
  while (copy.Next(&t)) ++n;
  return n;
}

long LineOfOffset(std::string_view text, std::size_t pos) {
  pos = std::min(pos, text.size());
  return 1 + static_cast<long>(std::count(text.begin(), text.begin() + pos, '\n'));
}

void CheckIsText(const std::string& file, std::string_view text, const char* format_name) {
  const void* nul = std::memchr(text.data(), '\0', text.size());
  if (!nul) return;
  const std::size_t pos = static_cast<std::size_t>(static_cast<const char*>(nul) - text.data());
  ThrowAtLine(file, LineOfOffset(text, pos),
              std::string("binary data (NUL byte) in a text ") + format_name + " file");
}

bool EqualsIgnoreCase(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(a[i])) !=
        std::tolower(static_cast<unsigned char>(b[i])))
      return false;
  }
  return true;
}

NumStatus ParseDouble(std::string_view tok, double* out) {
  if (!tok.empty() && tok[0] == '+') {
    tok.remove_prefix(1);
    if (!tok.empty() && (tok[0] == '-' || tok[0] == '+')) return NumStatus::kBad;
  }
  if (tok.empty()) return NumStatus::kBad;
  const char* end = tok.data() + tok.size();
  const auto [ptr, ec] = std::from_chars(tok.data(), end, *out, std::chars_format::general);
  if (ptr != end) return NumStatus::kBad;
  if (ec == std::errc::result_out_of_range) {
    // from_chars reports underflow too; a tiny value is harmlessly zero, an
    // overflow (1e999) is an error.
    double approx = std::strtod(std::string(tok).c_str(), nullptr);
    if (std::isfinite(approx)) {
      *out = approx;
      return NumStatus::kOk;
    }
    return NumStatus::kOutOfRange;
  }
  if (ec != std::errc()) return NumStatus::kBad;
  return NumStatus::kOk;
}

NumStatus ParseInt64(std::string_view tok, std::int64_t* out) {
  if (!tok.empty() && tok[0] == '+') {
    tok.remove_prefix(1);
    if (!tok.empty() && (tok[0] == '-' || tok[0] == '+')) return NumStatus::kBad;
  }
  if (tok.empty()) return NumStatus::kBad;
  const char* end = tok.data() + tok.size();
  const auto [ptr, ec] = std::from_chars(tok.data(), end, *out);
  if (ec == std::errc::result_out_of_range) return NumStatus::kOutOfRange;
  if (ec != std::errc() || ptr != end) return NumStatus::kBad;
  return NumStatus::kOk;
}

NumStatus ParseCoordinate(std::string_view tok, double* out, bool* rational) {
  *rational = false;
  const NumStatus st = ParseDouble(tok, out);
  if (st != NumStatus::kBad) return st;
  const std::size_t slash = tok.find('/');
  if (slash == std::string_view::npos) return NumStatus::kBad;
  std::int64_t p = 0, q = 0;
  const std::string_view ps = tok.substr(0, slash), qs = tok.substr(slash + 1);
  const NumStatus sp = ParseInt64(ps, &p), sq = ParseInt64(qs, &q);
  if (sp == NumStatus::kBad || sq == NumStatus::kBad) return NumStatus::kBad;
  *rational = true;
  if (sp == NumStatus::kOk && sq == NumStatus::kOk) {
    if (q == 0) return NumStatus::kBad;
    constexpr std::int64_t k2p53 = std::int64_t{1} << 53;
    if (p >= -k2p53 && p <= k2p53 && q >= -k2p53 && q <= k2p53) {
      // Both exactly representable: IEEE division rounds p/q correctly.
      *out = static_cast<double>(p) / static_cast<double>(q);
    } else {
      *out = static_cast<double>(static_cast<long double>(p) / static_cast<long double>(q));
    }
    return NumStatus::kOk;
  }
  // Integers beyond 64 bits: the best we can do is a double quotient.
  double pd = 0, qd = 0;
  if (ParseDouble(ps, &pd) != NumStatus::kOk || ParseDouble(qs, &qd) != NumStatus::kOk ||
      qd == 0)
    return NumStatus::kOutOfRange;
  *out = pd / qd;
  return std::isfinite(*out) ? NumStatus::kOk : NumStatus::kOutOfRange;
}

void AppendDouble(std::string* out, double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof(buf), v);
  out->append(buf, r.ptr);
}

void AppendInt(std::string* out, std::int64_t v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof(buf), v);
  out->append(buf, r.ptr);
}

std::string FormatDouble(double v) {
  std::string s;
  AppendDouble(&s, v);
  return s;
}

}  // namespace arcs::io_internal
