#include "framework/io/npz.h"

#include "framework/error.h"
#include "framework/io/io_util.h"

#include <zlib.h>

#include <cstring>

namespace arcs {
namespace {

using namespace io_internal;

std::uint32_t U32(std::string_view b, std::size_t at) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(b[at + i]);
  return v;
}
std::uint16_t U16(std::string_view b, std::size_t at) {
  return static_cast<std::uint16_t>(static_cast<unsigned char>(b[at]) | (static_cast<unsigned char>(b[at + 1]) << 8));
}
std::uint64_t U64(std::string_view b, std::size_t at) {
  return static_cast<std::uint64_t>(U32(b, at)) | (static_cast<std::uint64_t>(U32(b, at + 4)) << 32);
}
void Put16(std::string* s, std::uint32_t v) {
  s->push_back(static_cast<char>(v & 0xff));
  s->push_back(static_cast<char>((v >> 8) & 0xff));
}
void Put32(std::string* s, std::uint32_t v) {
  Put16(s, v & 0xffff);
  Put16(s, v >> 16);
}

std::string Inflate(const std::string& path, const std::string& member, std::string_view in, std::uint64_t out_size) {
  std::string out(static_cast<std::size_t>(out_size), '\0');
  z_stream zs{};
  if (inflateInit2(&zs, -MAX_WBITS) != Z_OK) throw InputError(path, 0, "member '" + member + "': zlib init failed");
  zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(in.data()));
  zs.avail_in = static_cast<uInt>(in.size());
  zs.next_out = reinterpret_cast<Bytef*>(out.data());
  zs.avail_out = static_cast<uInt>(out.size());
  const int rc = inflate(&zs, Z_FINISH);
  const std::uint64_t got = zs.total_out;
  inflateEnd(&zs);
  if (rc != Z_STREAM_END || got != out_size)
    throw InputError(path, 0, "member '" + member + "': corrupt deflate data (" + std::to_string(got) + " of " +
                                  std::to_string(out_size) + " bytes inflated)");
  return out;
}

}  // namespace

std::vector<std::pair<std::string, NpyArray>> ReadNpz(const std::string& path) {
  const FileBytes file = ReadWholeFile(path);
  const std::string_view b = file.view();
  if (b.size() < 22 || U32(b, 0) != 0x04034b50)
    ThrowAtOffset(path, 0, "not an .npz file (no zip signature PK\\3\\4)");
  // End of central directory: the last "PK\5\6" within the final 64 KiB + 22.
  std::size_t eocd = std::string_view::npos;
  for (std::size_t i = b.size() - 22 + 1; i-- > 0 && b.size() - i <= 65557;)
    if (U32(b, i) == 0x06054b50) {
      eocd = i;
      break;
    }
  if (eocd == std::string_view::npos) ThrowAtOffset(path, b.size(), "zip end-of-central-directory record not found (truncated file?)");
  std::uint64_t count = U16(b, eocd + 10), cd = U32(b, eocd + 16);
  if ((count == 0xffff || cd == 0xffffffff) && eocd >= 20 && U32(b, eocd - 20) == 0x07064b50) {
    const std::uint64_t z64 = U64(b, eocd - 20 + 8);
    if (z64 + 56 > b.size() || U32(b, z64) != 0x06064b50) ThrowAtOffset(path, eocd - 20, "bad zip64 end record");
    count = U64(b, z64 + 32);
    cd = U64(b, z64 + 48);
  }
  std::vector<std::pair<std::string, NpyArray>> out;
  std::size_t at = cd;
  for (std::uint64_t e = 0; e < count; ++e) {
    if (at + 46 > b.size() || U32(b, at) != 0x02014b50) ThrowAtOffset(path, at, "bad zip central directory entry");
    const int method = U16(b, at + 10);
    std::uint64_t csize = U32(b, at + 20), usize = U32(b, at + 24);
    const std::size_t nlen = U16(b, at + 28), xlen = U16(b, at + 30), clen = U16(b, at + 32);
    std::uint64_t local = U32(b, at + 42);
    if (at + 46 + nlen + xlen + clen > b.size()) ThrowAtOffset(path, at, "zip central directory entry runs past the end");
    const std::string name(b.substr(at + 46, nlen));
    // zip64 extra field: the 0xffffffff values, in the order usize, csize, offset.
    for (std::size_t x = at + 46 + nlen; x + 4 <= at + 46 + nlen + xlen;) {
      const int id = U16(b, x), len = U16(b, x + 2);
      if (id == 0x0001) {
        std::size_t p = x + 4;
        if (usize == 0xffffffff && p + 8 <= x + 4 + len) usize = U64(b, p), p += 8;
        if (csize == 0xffffffff && p + 8 <= x + 4 + len) csize = U64(b, p), p += 8;
        if (local == 0xffffffff && p + 8 <= x + 4 + len) local = U64(b, p), p += 8;
      }
      x += 4 + len;
    }
    at += 46 + nlen + xlen + clen;
    if (local + 30 > b.size() || U32(b, local) != 0x04034b50) ThrowAtOffset(path, local, "bad zip local header of '" + name + "'");
    const std::uint64_t data = local + 30 + U16(b, local + 26) + U16(b, local + 28);
    if (data + csize > b.size()) ThrowAtOffset(path, data, "member '" + name + "' runs past the end of the file");
    std::string_view raw = b.substr(data, csize);
    std::string inflated;
    if (method == 8) {
      inflated = Inflate(path, name, raw, usize);
      raw = inflated;
    } else if (method != 0) {
      throw InputError(path, 0, "member '" + name + "': unsupported zip compression method " + std::to_string(method) +
                                    " (supported: stored, deflate)");
    }
    std::string key = name;
    if (key.size() > 4 && key.compare(key.size() - 4, 4, ".npy") == 0) key.resize(key.size() - 4);
    out.emplace_back(key, ParseNpy(path + ": member '" + name + "'", raw));
  }
  if (out.empty()) ThrowAtOffset(path, 0, "the archive has no members");
  return out;
}

void WriteNpz(const std::string& path, const std::vector<NpzMember>& members) {
  std::string zip, central;
  for (const NpzMember& m : members) {
    const std::string name = m.name + ".npy";
    const std::string npy = EncodeNpy(m.data.data(), m.shape);
    if (npy.size() >= 0xffffffffu || zip.size() >= 0xffffffffu)
      throw Error("cannot write '" + path + "': member '" + name + "' needs zip64 (over 4 GiB)");
    const std::uint32_t crc = static_cast<std::uint32_t>(
        crc32(0L, reinterpret_cast<const Bytef*>(npy.data()), static_cast<uInt>(npy.size())));
    const std::uint32_t offset = static_cast<std::uint32_t>(zip.size());
    // Local header: version 2.0, no flags, stored, DOS time 1980-01-01.
    Put32(&zip, 0x04034b50);
    Put16(&zip, 20); Put16(&zip, 0); Put16(&zip, 0); Put16(&zip, 0); Put16(&zip, 0x21);
    Put32(&zip, crc); Put32(&zip, static_cast<std::uint32_t>(npy.size())); Put32(&zip, static_cast<std::uint32_t>(npy.size()));
    Put16(&zip, static_cast<std::uint32_t>(name.size())); Put16(&zip, 0);
    zip += name;
    zip += npy;
    Put32(&central, 0x02014b50);
    Put16(&central, 20); Put16(&central, 20); Put16(&central, 0); Put16(&central, 0); Put16(&central, 0); Put16(&central, 0x21);
    Put32(&central, crc); Put32(&central, static_cast<std::uint32_t>(npy.size())); Put32(&central, static_cast<std::uint32_t>(npy.size()));
    Put16(&central, static_cast<std::uint32_t>(name.size())); Put16(&central, 0); Put16(&central, 0);
    Put16(&central, 0); Put16(&central, 0); Put32(&central, 0); Put32(&central, offset);
    central += name;
  }
  const std::uint32_t cd_offset = static_cast<std::uint32_t>(zip.size());
  zip += central;
  Put32(&zip, 0x06054b50);
  Put16(&zip, 0); Put16(&zip, 0);
  Put16(&zip, static_cast<std::uint32_t>(members.size())); Put16(&zip, static_cast<std::uint32_t>(members.size()));
  Put32(&zip, static_cast<std::uint32_t>(central.size())); Put32(&zip, cd_offset); Put16(&zip, 0);
  WriteWholeFile(path, zip);
}

}  // namespace arcs
