#include "framework/io/points_io.h"

#include "framework/io/lzf.h"

#include "framework/io/io_util.h"
#include "framework/io/ply.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstring>

namespace arcs {
namespace {

using namespace io_internal;

// Collected points before they become a PointCloud.
struct RawPoints {
  std::vector<double> p;  // 3 per point
  std::vector<double> n;  // 3 per point when normals
  bool normals = false;
};

PointCloud ToCloud(const std::string& path, RawPoints&& raw) {
  const std::size_t np = raw.p.size() / 3;
  if (np > static_cast<std::size_t>(INT_MAX)) throw InputError(path, 0, "more than 2^31 points");
  PointCloud pc;
  pc.P.resize(static_cast<Eigen::Index>(np), 3);
  if (np) std::memcpy(pc.P.data(), raw.p.data(), raw.p.size() * sizeof(double));
  if (raw.normals) {
    pc.N.resize(static_cast<Eigen::Index>(np), 3);
    if (np) std::memcpy(pc.N.data(), raw.n.data(), raw.n.size() * sizeof(double));
  }
  return pc;
}

void SummariseSkipped(PointReadReport* rep, std::size_t first, const char* what) {
  const std::size_t n = rep->skipped_lines.size() - first;
  if (n > 0)
    rep->warnings.push_back(std::to_string(n) + " " + what + " skipped (first at line " +
                            std::to_string(rep->skipped_lines[first]) + ")");
}

// ---- PLY -------------------------------------------------------------------

PointCloud ReadPlyPoints(const std::string& path, std::string_view bytes, PointReadReport* rep) {
  PlyRequest req;
  req.want_normals = true;
  req.want_faces = false;
  req.nonfinite_is_error = false;
  PlyData d = ReadPly(path, bytes, req);
  for (auto& w : d.warnings) rep->warnings.push_back(std::move(w));
  RawPoints raw;
  raw.normals = d.has_normals;
  if (d.nonfinite.empty()) {
    raw.p = std::move(d.xyz);
    raw.n = std::move(d.normals);
    return ToCloud(path, std::move(raw));
  }
  std::size_t bad = 0;
  const std::size_t first_skipped = rep->skipped_lines.size();
  for (std::int64_t i = 0; i < d.num_vertices; ++i) {
    if (bad < d.nonfinite.size() && d.nonfinite[bad].index == i) {
      if (!d.binary) rep->skipped_lines.push_back(static_cast<long>(d.nonfinite[bad].location));
      ++bad;
      continue;
    }
    raw.p.insert(raw.p.end(), d.xyz.begin() + 3 * i, d.xyz.begin() + 3 * i + 3);
    if (raw.normals) raw.n.insert(raw.n.end(), d.normals.begin() + 3 * i, d.normals.begin() + 3 * i + 3);
  }
  if (d.binary) {
    rep->warnings.push_back(std::to_string(d.nonfinite.size()) +
                            " points with a non-finite coordinate skipped (first at offset " +
                            std::to_string(d.nonfinite[0].location) + ")");
  } else {
    SummariseSkipped(rep, first_skipped, "points with a non-finite coordinate");
  }
  return ToCloud(path, std::move(raw));
}

// ---- XYZ -------------------------------------------------------------------

PointCloud ReadXyz(const std::string& path, std::string_view text, PointReadReport* rep) {
  CheckIsText(path, text, "point");
  LineReader lines(text);
  std::string_view line, tok;
  RawPoints raw;
  int cols = 0;
  const std::size_t first_skipped = rep->skipped_lines.size();
  long nonfinite = 0;
  double v[6];
  while (lines.Next(&line)) {
    Tokenizer tk(StripComment(line));
    int n = 0;
    bool ok = true, finite = true;
    while (tk.Next(&tok)) {
      if (n == 6) {
        ok = false;
        break;
      }
      if (ParseDouble(tok, &v[n]) != NumStatus::kOk) {
        ok = false;
        break;
      }
      finite = finite && std::isfinite(v[n]);
      ++n;
    }
    if (n == 0 && ok) continue;  // blank or comment
    if (!ok || (n != 3 && n != 6) || (cols != 0 && n != cols)) {
      rep->skipped_lines.push_back(lines.line());
      continue;
    }
    if (!finite) {
      rep->skipped_lines.push_back(lines.line());
      ++nonfinite;
      continue;
    }
    cols = n;
    raw.p.insert(raw.p.end(), v, v + 3);
    if (n == 6) raw.n.insert(raw.n.end(), v + 3, v + 6);
  }
  if (cols == 0) {
    const long first = rep->skipped_lines.size() > first_skipped ? rep->skipped_lines[first_skipped] : 0;
    ThrowAtLine(path, first,
                "no valid point line ('x y z' or 'x y z nx ny nz') in the file (" +
                    std::to_string(rep->skipped_lines.size() - first_skipped) +
                    " malformed lines)");
  }
  raw.normals = cols == 6;
  SummariseSkipped(rep, first_skipped, "malformed or non-finite lines");
  if (nonfinite > 0)
    rep->warnings.push_back(std::to_string(nonfinite) + " of them with non-finite values");
  return ToCloud(path, std::move(raw));
}

// ---- PCD -------------------------------------------------------------------

struct PcdField {
  std::string name;
  int size = 4;
  char type = 'F';
  int count = 1;
  int offset = 0;  // byte offset in a binary point / first token index in ASCII
};

double LoadPcd(const char* p, const PcdField& f) {
  switch (f.type) {
    case 'F': return f.size == 4 ? static_cast<double>(Load<float>(p, true)) : Load<double>(p, true);
    case 'I':
      switch (f.size) {
        case 1: return static_cast<std::int8_t>(*p);
        case 2: return Load<std::int16_t>(p, true);
        case 4: return Load<std::int32_t>(p, true);
        default: return static_cast<double>(Load<std::int64_t>(p, true));
      }
    default:
      switch (f.size) {
        case 1: return static_cast<std::uint8_t>(*p);
        case 2: return Load<std::uint16_t>(p, true);
        case 4: return Load<std::uint32_t>(p, true);
        default: return static_cast<double>(Load<std::uint64_t>(p, true));
      }
  }
}

PointCloud ReadPcd(const std::string& path, std::string_view bytes, PointReadReport* rep) {
  LineReader lines(bytes);
  std::string_view line, kw, tok;
  std::vector<PcdField> fields;
  std::vector<int> sizes, counts;
  std::vector<char> types;
  std::int64_t width = -1, height = -1, points = -1;
  std::string data;
  long fields_line = 0;
  auto read_int = [&](std::int64_t* out) {
    Tokenizer tk(line);
    tk.Next(&tok);
    if (!tk.Next(&tok) || ParseInt64(tok, out) != NumStatus::kOk || *out < 0)
      ThrowAtLine(path, lines.line(), "expected a non-negative integer after " + Quote(kw));
  };
  while (data.empty()) {
    if (!lines.Next(&line)) ThrowAtLine(path, lines.line(), "PCD header has no DATA line");
    const long ln = lines.line();
    if (line.find('\0') != std::string_view::npos)
      ThrowAtLine(path, ln, "binary data inside the PCD header");
    Tokenizer tk(line);
    if (!tk.Next(&kw) || kw[0] == '#') continue;
    if (kw == "VERSION" || kw == "VIEWPOINT") continue;
    if (kw == "FIELDS") {
      fields_line = ln;
      while (tk.Next(&tok)) {
        PcdField f;
        f.name = std::string(tok);
        fields.push_back(f);
      }
    } else if (kw == "SIZE" || kw == "COUNT") {
      auto& vec = kw == "SIZE" ? sizes : counts;
      while (tk.Next(&tok)) {
        std::int64_t v = 0;
        if (ParseInt64(tok, &v) != NumStatus::kOk || v < 1 || v > 1 << 20)
          ThrowAtLine(path, ln, "bad " + std::string(kw) + " value " + Quote(tok));
        vec.push_back(static_cast<int>(v));
      }
    } else if (kw == "TYPE") {
      while (tk.Next(&tok)) {
        if (tok.size() != 1 || (tok[0] != 'F' && tok[0] != 'I' && tok[0] != 'U'))
          ThrowAtLine(path, ln, "bad TYPE " + Quote(tok) + " (expected F, I or U)");
        types.push_back(tok[0]);
      }
    } else if (kw == "WIDTH") {
      read_int(&width);
    } else if (kw == "HEIGHT") {
      read_int(&height);
    } else if (kw == "POINTS") {
      read_int(&points);
    } else if (kw == "DATA") {
      if (!tk.Next(&tok)) ThrowAtLine(path, ln, "DATA needs ascii, binary or binary_compressed");
      if (tok != "ascii" && tok != "binary" && tok != "binary_compressed")
        ThrowAtLine(path, ln, "unknown PCD DATA type " + Quote(tok));
      data = std::string(tok);
    } else {
      ThrowAtLine(path, ln, "unknown PCD header keyword " + Quote(kw));
    }
  }
  const long data_line = lines.line();
  if (fields.empty()) ThrowAtLine(path, data_line, "PCD header has no FIELDS line");
  if (counts.empty()) counts.assign(fields.size(), 1);
  if (sizes.size() != fields.size() || types.size() != fields.size() ||
      counts.size() != fields.size())
    ThrowAtLine(path, fields_line,
                "FIELDS, SIZE, TYPE and COUNT must have the same length (" +
                    std::to_string(fields.size()) + " fields)");
  int stride = 0, ntok = 0;
  for (std::size_t i = 0; i < fields.size(); ++i) {
    PcdField& f = fields[i];
    f.size = sizes[i];
    f.type = types[i];
    f.count = counts[i];
    const bool ok = f.type == 'F' ? (f.size == 4 || f.size == 8)
                                  : (f.size == 1 || f.size == 2 || f.size == 4 || f.size == 8);
    if (!ok)
      ThrowAtLine(path, fields_line,
                  "field '" + f.name + "' has an unsupported TYPE/SIZE " + f.type + "/" +
                      std::to_string(f.size));
    f.offset = data != "ascii" ? stride : ntok;
    stride += f.size * f.count;
    ntok += f.count;
    if (stride > (1 << 28))  // sizes and counts are <= 2^20 each; many fields could overflow int
      ThrowAtLine(path, fields_line, "a PCD point of more than 2^28 bytes");
  }
  auto find = [&](const char* name) -> const PcdField* {
    for (const PcdField& f : fields) {
      if (f.name == name) return &f;
    }
    return nullptr;
  };
  const PcdField* fx = find("x");
  const PcdField* fy = find("y");
  const PcdField* fz = find("z");
  if (!fx || !fy || !fz) ThrowAtLine(path, fields_line, "PCD needs the fields x, y and z");
  const PcdField* fn[3] = {find("normal_x"), find("normal_y"), find("normal_z")};
  const bool normals = fn[0] && fn[1] && fn[2];
  const PcdField* use[6] = {fx, fy, fz, fn[0], fn[1], fn[2]};
  if (points < 0) {
    if (width < 0 || height < 0) ThrowAtLine(path, data_line, "PCD header has no POINTS count");
    if (width > 0 && height > (std::int64_t{1} << 62) / width)
      ThrowAtLine(path, data_line, "PCD WIDTH x HEIGHT overflows");
    points = width * height;
  }
  RawPoints raw;
  raw.normals = normals;
  std::size_t body = lines.offset();
  const int nused = normals ? 6 : 3;
  std::string decoded;  // binary_compressed: the points re-laid out as "binary" (one record per point)
  if (data == "binary_compressed") {
    // PCL's layout: u32 compressed size, u32 uncompressed size, LZF data that
    // decodes to the fields one after another (all x, then all y, ...).
    if (bytes.size() - body < 8) ThrowAtOffset(path, body, "binary_compressed data has no size header");
    const std::uint32_t csize = Load<std::uint32_t>(bytes.data() + body, true);
    const std::uint32_t usize = Load<std::uint32_t>(bytes.data() + body + 4, true);
    if (csize > bytes.size() - body - 8)
      ThrowAtOffset(path, body, "binary_compressed data says " + std::to_string(csize) + " compressed bytes, the file has " +
                                    std::to_string(bytes.size() - body - 8));
    if (static_cast<std::uint64_t>(usize) != static_cast<std::uint64_t>(points) * stride)
      ThrowAtOffset(path, body + 4, "binary_compressed data decodes to " + std::to_string(usize) + " bytes, but " +
                                        std::to_string(points) + " points of " + std::to_string(stride) + " bytes need " +
                                        std::to_string(static_cast<std::uint64_t>(points) * stride));
    std::string soa(usize, '\0');
    const std::string err = LzfDecompress(reinterpret_cast<const unsigned char*>(bytes.data() + body + 8), csize,
                                          reinterpret_cast<unsigned char*>(soa.data()), usize);
    if (!err.empty()) ThrowAtOffset(path, body + 8, err + " (offsets within the compressed data)");
    decoded.assign(usize, '\0');
    std::size_t field_start = 0;
    for (const PcdField& f : fields) {
      const std::size_t w = static_cast<std::size_t>(f.size) * f.count;
      for (std::int64_t i = 0; i < points; ++i)
        std::memcpy(decoded.data() + static_cast<std::size_t>(i) * stride + f.offset,
                    soa.data() + field_start + static_cast<std::size_t>(i) * w, w);
      field_start += w * static_cast<std::size_t>(points);
    }
    bytes = decoded;
    body = 0;
    data = "binary";
  }
  const std::uint64_t remaining = bytes.size() - body;
  if (data == "binary") {
    if (static_cast<std::uint64_t>(points) > remaining / static_cast<std::uint64_t>(stride))
      ThrowAtOffset(path, body,
                    "data shorter than the header says: " + std::to_string(points) + " points of " +
                        std::to_string(stride) + " bytes need more than the " +
                        std::to_string(remaining) + " bytes left");
    raw.p.reserve(3 * static_cast<std::size_t>(points));
    std::int64_t skipped = 0, first_bad = -1;
    for (std::int64_t i = 0; i < points; ++i) {
      const char* base = bytes.data() + body + static_cast<std::size_t>(i) * stride;
      double v[6];
      bool finite = true;
      for (int k = 0; k < nused; ++k) {
        v[k] = LoadPcd(base + use[k]->offset, *use[k]);
        finite = finite && std::isfinite(v[k]);
      }
      if (!finite) {
        if (first_bad < 0) first_bad = static_cast<std::int64_t>(body) + i * stride;
        ++skipped;
        continue;
      }
      raw.p.insert(raw.p.end(), v, v + 3);
      if (normals) raw.n.insert(raw.n.end(), v + 3, v + 6);
    }
    if (skipped > 0)
      rep->warnings.push_back(std::to_string(skipped) +
                              " points with a non-finite coordinate skipped (first at offset " +
                              std::to_string(first_bad) + ")");
    return ToCloud(path, std::move(raw));
  }
  // ASCII: one point per line with `ntok` values.
  CheckIsText(path, bytes.substr(body), "PCD");
  // POINTS is not trusted for allocation: a point needs >= 2 bytes per value,
  // so a lying header reserves at most what the file could hold; a short
  // file fails at its last line.
  raw.p.reserve(3 * static_cast<std::size_t>(std::min<std::uint64_t>(
                        static_cast<std::uint64_t>(points),
                        (remaining + 1) / (2 * static_cast<std::uint64_t>(ntok)) + 1)));
  const std::size_t first_skipped = rep->skipped_lines.size();
  std::vector<std::string_view> toks(ntok);
  std::int64_t got = 0;
  while (got < points) {
    if (!lines.Next(&line))
      ThrowAtLine(path, lines.line(),
                  "unexpected end of file: expected " + std::to_string(points) +
                      " points, found " + std::to_string(got));
    Tokenizer tk(line);
    int n = 0;
    while (n < ntok && tk.Next(&toks[n])) ++n;
    if (n == 0) continue;
    if (n < ntok || tk.Next(&tok))
      ThrowAtLine(path, lines.line(),
                  "expected " + std::to_string(ntok) + " values per point, found " +
                      std::to_string(Tokenizer(line).CountRemaining()));
    double v[6];
    bool finite = true;
    for (int k = 0; k < nused; ++k) {
      const std::string_view t = toks[use[k]->offset];
      if (ParseDouble(t, &v[k]) != NumStatus::kOk)
        ThrowAtLine(path, lines.line(), "bad number " + Quote(t) + " for field '" + use[k]->name + "'");
      finite = finite && std::isfinite(v[k]);
    }
    ++got;
    if (!finite) {
      rep->skipped_lines.push_back(lines.line());
      continue;
    }
    raw.p.insert(raw.p.end(), v, v + 3);
    if (normals) raw.n.insert(raw.n.end(), v + 3, v + 6);
  }
  SummariseSkipped(rep, first_skipped, "points with a non-finite coordinate");
  return ToCloud(path, std::move(raw));
}

}  // namespace

PointCloud ReadPointCloud(const std::string& path, PointReadReport* report) {
  const std::string ext = LowerExtension(path);
  const bool text = ext == ".xyz" || ext == ".pwn" || ext == ".txt";
  if (ext != ".ply" && ext != ".pcd" && !text)
    throw InputError(path, 0,
                     "unsupported point cloud format '" + ext +
                         "' (supported: .ply .xyz .pwn .txt .pcd)");
  PointReadReport local;
  PointReadReport* rep = report ? report : &local;
  *rep = PointReadReport();
  const FileBytes file = ReadWholeFile(path);
  const std::string_view bytes = file.view();
  if (ext == ".ply") return ReadPlyPoints(path, bytes, rep);
  if (ext == ".pcd") return ReadPcd(path, bytes, rep);
  return ReadXyz(path, bytes, rep);
}

void WritePointCloud(const std::string& path, const PointCloud& pc) {
  const std::string ext = LowerExtension(path);
  const bool text = ext == ".xyz" || ext == ".pwn" || ext == ".txt";
  if (ext != ".ply" && !text)
    throw InputError(path, 0,
                     "unsupported point cloud format '" + ext +
                         "' for writing (supported: .ply .xyz .pwn .txt)");
  if (pc.N.rows() != 0 && pc.N.rows() != pc.P.rows())
    throw Error("cannot write '" + path + "': " + std::to_string(pc.P.rows()) + " points but " +
                std::to_string(pc.N.rows()) + " normals");
  if (!pc.P.allFinite() || !pc.N.allFinite())
    throw Error("cannot write '" + path + "': non-finite coordinates");
  const bool normals = pc.HasNormals();
  const int n = pc.Size();
  std::string out;
  if (ext == ".ply") {
    out = "ply\nformat binary_little_endian 1.0\ncomment written by arcs\nelement vertex " +
          std::to_string(n) + "\nproperty double x\nproperty double y\nproperty double z\n";
    if (normals) out += "property double nx\nproperty double ny\nproperty double nz\n";
    out += "end_header\n";
    out.reserve(out.size() + static_cast<std::size_t>(n) * (normals ? 48 : 24));
    for (int i = 0; i < n; ++i) {
      for (int a = 0; a < 3; ++a) AppendLE<double>(&out, pc.P(i, a));
      if (normals) {
        for (int a = 0; a < 3; ++a) AppendLE<double>(&out, pc.N(i, a));
      }
    }
  } else {
    out.reserve(static_cast<std::size_t>(n) * (normals ? 120 : 60));
    for (int i = 0; i < n; ++i) {
      for (int a = 0; a < 3; ++a) {
        if (a) out += ' ';
        AppendDouble(&out, pc.P(i, a));
      }
      if (normals) {
        for (int a = 0; a < 3; ++a) {
          out += ' ';
          AppendDouble(&out, pc.N(i, a));
        }
      }
      out += '\n';
    }
  }
  WriteWholeFile(path, out);
}

}  // namespace arcs
