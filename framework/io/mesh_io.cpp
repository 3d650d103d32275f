#include "framework/io/mesh_io.h"

#include "framework/io/io_util.h"
#include "framework/io/ply.h"

#include <algorithm>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstring>
#include <map>
#include <unordered_map>

namespace arcs {
namespace {

using namespace io_internal;

// Positions and triangles as read, before they become a Mesh.
struct RawMesh {
  std::vector<double> xyz;  // 3 per vertex
  std::vector<int> tris;    // 3 per triangle
};

void CheckVertexCount(const std::string& path, long line, std::size_t nv) {
  if (nv > static_cast<std::size_t>(INT_MAX)) ThrowAtLine(path, line, "more than 2^31 vertices");
}

// Fan triangulation (v0, vk, vk+1) of one polygon with >= 3 vertices.
template <class Index>
void AddFan(const std::vector<Index>& poly, RawMesh* m, MeshReadReport* rep) {
  if (poly.size() > 3) ++rep->polygons_triangulated;
  for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
    m->tris.push_back(static_cast<int>(poly[0]));
    m->tris.push_back(static_cast<int>(poly[k]));
    m->tris.push_back(static_cast<int>(poly[k + 1]));
  }
}

// Parses one coordinate token of a text format; throws at `line` on bad,
// out-of-range or non-finite values.
double ParseCoord(const std::string& path, long line, std::string_view tok,
                  MeshReadReport* rep) {
  double v = 0;
  bool rational = false;
  const NumStatus st = ParseCoordinate(tok, &v, &rational);
  if (st == NumStatus::kBad) ThrowAtLine(path, line, "bad vertex coordinate " + Quote(tok));
  if (st == NumStatus::kOutOfRange)
    ThrowAtLine(path, line, "vertex coordinate " + Quote(tok) + " is out of the double range");
  if (!std::isfinite(v)) ThrowAtLine(path, line, "non-finite vertex coordinate " + Quote(tok));
  if (rational) ++rep->rational_coordinates;
  return v;
}

// ---- OBJ -------------------------------------------------------------------

bool IsIgnoredObjKeyword(std::string_view kw) {
  static const char* const kIgnored[] = {
      "vt",   "vn",   "vp",   "g",     "o",     "s",      "usemtl", "mtllib", "l",
      "p",    "cstype", "deg", "bmat", "step",  "curv",   "curv2",  "surf",   "parm",
      "trim", "hole", "scrv", "sp",    "end",   "con",    "mg",     "lod",    "usemap",
      "maplib", "shadow_obj", "trace_obj", "ctech", "stech", "bevel", "c_interp", "d_interp",
      "call", "csh"};
  for (const char* k : kIgnored) {
    if (kw == k) return true;
  }
  return false;
}

// Number of 'v' statements: lets face indices be range-checked where they
// appear (positive indices may legally refer to vertices defined later).
std::int64_t CountObjVertices(std::string_view text) {
  std::int64_t n = 0;
  // A UTF-8 byte-order mark is skipped, as LineReader does (else the first
  // line's vertex goes uncounted and the last face index is "out of range").
  std::size_t i = text.substr(0, 3) == "\xEF\xBB\xBF" ? 3 : 0;
  const std::size_t size = text.size();
  while (i < size) {
    while (i < size && IsSpace(text[i])) ++i;
    if (i + 1 < size && text[i] == 'v' && IsSpace(text[i + 1])) ++n;
    const void* nl = std::memchr(text.data() + i, '\n', size - i);
    if (!nl) break;
    i = static_cast<std::size_t>(static_cast<const char*>(nl) - text.data()) + 1;
  }
  return n;
}

void ReadObj(const std::string& path, std::string_view text, RawMesh* m, MeshReadReport* rep) {
  CheckIsText(path, text, "OBJ");
  const std::int64_t total_v = CountObjVertices(text);
  CheckVertexCount(path, 0, static_cast<std::size_t>(total_v));
  LineReader lines(text);
  std::string_view line, kw, tok;
  std::vector<std::int64_t> poly;
  std::map<std::string, std::pair<long, long>> unknown;  // keyword -> (first line, count)
  m->xyz.reserve(3 * static_cast<std::size_t>(total_v));
  m->tris.reserve(text.size() / 8);
  std::int64_t nv = 0;
  while (lines.Next(&line)) {
    Tokenizer tk(line);
    if (!tk.Next(&kw) || kw[0] == '#') continue;
    const long ln = lines.line();
    if (kw == "v") {
      int k = 0;
      for (; k < 3 && tk.Next(&tok); ++k) m->xyz.push_back(ParseCoord(path, ln, tok, rep));
      if (k < 3)
        ThrowAtLine(path, ln, "vertex has " + std::to_string(k) + " coordinates, expected 3");
      ++nv;
    } else if (kw == "f") {
      poly.clear();
      while (tk.Next(&tok)) {
        const char* b = tok.data();
        const char* e = b + tok.size();
        if (*b == '+') ++b;
        std::int64_t v = 0;
        const auto [ptr, ec] = std::from_chars(b, e, v);
        if (ec != std::errc() || (ptr != e && *ptr != '/'))
          ThrowAtLine(path, ln, "bad face vertex " + Quote(tok));
        if (v == 0) ThrowAtLine(path, ln, "face vertex index 0 (OBJ indices start at 1)");
        std::int64_t idx;
        if (v < 0) {
          idx = nv + v;
          if (idx < 0)
            ThrowAtLine(path, ln,
                        "relative face vertex index " + std::to_string(v) + " refers before the "
                        "first vertex (" + std::to_string(nv) + " vertices so far)");
        } else {
          idx = v - 1;
          if (idx >= total_v)
            ThrowAtLine(path, ln,
                        "face vertex index " + std::to_string(v) +
                            " out of range (the file has " + std::to_string(total_v) +
                            " vertices)");
        }
        poly.push_back(idx);
      }
      if (poly.size() < 3)
        ThrowAtLine(path, ln,
                    "face has " + std::to_string(poly.size()) +
                        " vertices (a face needs at least 3)");
      AddFan(poly, m, rep);
    } else if (!IsIgnoredObjKeyword(kw)) {
      auto it = unknown.find(std::string(kw));
      if (it == unknown.end()) {
        unknown.emplace(std::string(kw), std::make_pair(ln, 1L));
      } else {
        ++it->second.second;
      }
    }
  }
  for (const auto& [k, v] : unknown) {
    rep->warnings.push_back("unknown OBJ statement " + Quote(k) + " ignored (" +
                            std::to_string(v.second) + " lines, first at line " +
                            std::to_string(v.first) + ")");
  }
}

// ---- OFF -------------------------------------------------------------------

void ReadOff(const std::string& path, std::string_view text, RawMesh* m, MeshReadReport* rep) {
  CheckIsText(path, text, "OFF");
  LineReader lines(text);
  std::string_view line, tok;
  // The next line with content ('#' comments and blank lines skipped).
  auto next_content = [&]() {
    while (lines.Next(&line)) {
      line = StripComment(line);
      if (!IsBlank(line)) return true;
    }
    return false;
  };
  if (!next_content()) ThrowAtLine(path, 0, "empty OFF file");
  std::vector<std::string_view> counts;
  {
    Tokenizer tk(line);
    std::string_view first;
    tk.Next(&first);
    if (first.size() >= 3 && first.substr(first.size() - 3) == "OFF") {
      const std::string_view prefix = first.substr(0, first.size() - 3);
      for (char c : prefix) {
        if (c == '4' || c == 'n')
          ThrowAtLine(path, lines.line(), "OFF variant " + Quote(first) +
                                              " (4D / n-dimensional) is not supported");
        if (c != 'S' && c != 'T' && c != 'C' && c != 'N')
          ThrowAtLine(path, lines.line(), "unknown OFF header " + Quote(first));
      }
      while (tk.Next(&tok)) {
        if (tok == "BINARY") ThrowAtLine(path, lines.line(), "binary OFF is not supported");
        counts.push_back(tok);
      }
      if (counts.empty()) {
        if (!next_content())
          ThrowAtLine(path, lines.line(),
                      "unexpected end of file: expected the counts 'V F [E]' after the header");
        Tokenizer tc(line);
        while (tc.Next(&tok)) counts.push_back(tok);
      }
    } else {
      std::int64_t probe = 0;
      if (ParseInt64(first, &probe) != NumStatus::kOk)
        ThrowAtLine(path, lines.line(), "not an OFF file: expected 'OFF', found " + Quote(first));
      rep->warnings.push_back("OFF file without the 'OFF' keyword");
      counts.push_back(first);
      while (tk.Next(&tok)) counts.push_back(tok);
    }
  }
  const long count_line = lines.line();
  std::int64_t nv = 0, nf = 0;
  if (counts.size() < 2 || ParseInt64(counts[0], &nv) != NumStatus::kOk ||
      ParseInt64(counts[1], &nf) != NumStatus::kOk || nv < 0 || nf < 0)
    ThrowAtLine(path, count_line, "expected the counts 'V F [E]' (non-negative integers)");
  CheckVertexCount(path, count_line, static_cast<std::size_t>(nv));
  // Counts are not trusted for allocation: each vertex line needs >= 6 bytes
  // ("0 0 0\n") and each face >= 8 ("3 0 1 2\n"), so a lying header reserves
  // at most what the file could hold, and parsing stops at the real end of
  // file with the line where the data runs out.
  const std::uint64_t remaining = text.size() - lines.offset();
  m->xyz.reserve(3 * static_cast<std::size_t>(std::min<std::uint64_t>(nv, remaining / 6 + 1)));
  m->tris.reserve(3 * static_cast<std::size_t>(std::min<std::uint64_t>(nf, remaining / 8 + 1)));
  for (std::int64_t i = 0; i < nv; ++i) {
    if (!next_content())
      ThrowAtLine(path, lines.line(),
                  "unexpected end of file: expected " + std::to_string(nv) + " vertices, found " +
                      std::to_string(i));
    Tokenizer tk(line);
    int k = 0;
    for (; k < 3 && tk.Next(&tok); ++k) m->xyz.push_back(ParseCoord(path, lines.line(), tok, rep));
    if (k < 3)
      ThrowAtLine(path, lines.line(),
                  "vertex " + std::to_string(i) + " has " + std::to_string(k) +
                      " coordinates, expected 3");
  }
  std::vector<std::int64_t> poly;
  for (std::int64_t i = 0; i < nf; ++i) {
    if (!next_content())
      ThrowAtLine(path, lines.line(),
                  "unexpected end of file: expected " + std::to_string(nf) + " faces, found " +
                      std::to_string(i));
    const long ln = lines.line();
    Tokenizer tk(line);
    std::int64_t n = 0;
    tk.Next(&tok);
    if (ParseInt64(tok, &n) != NumStatus::kOk || n < 0)
      ThrowAtLine(path, ln, "bad face vertex count " + Quote(tok));
    if (n < 3)
      ThrowAtLine(path, ln,
                  "face " + std::to_string(i) + " has " + std::to_string(n) +
                      " vertices (a face needs at least 3)");
    poly.clear();
    for (std::int64_t j = 0; j < n; ++j) {
      if (!tk.Next(&tok))
        ThrowAtLine(path, ln,
                    "face " + std::to_string(i) + " announces " + std::to_string(n) +
                        " vertices but lists " + std::to_string(j));
      std::int64_t v = 0;
      if (ParseInt64(tok, &v) != NumStatus::kOk)
        ThrowAtLine(path, ln, "bad face vertex index " + Quote(tok));
      if (v < 0 || v >= nv)
        ThrowAtLine(path, ln,
                    "face vertex index " + std::to_string(v) + " out of range [0, " +
                        std::to_string(nv) + ")");
      poly.push_back(v);
    }
    AddFan(poly, m, rep);
  }
  if (next_content())
    rep->warnings.push_back("content after the last face (from line " +
                            std::to_string(lines.line()) + ") ignored");
}

// ---- PLY -------------------------------------------------------------------

void ReadPlyMesh(const std::string& path, std::string_view bytes, RawMesh* m,
                 MeshReadReport* rep) {
  PlyRequest req;
  req.want_faces = true;
  req.nonfinite_is_error = true;
  PlyData d = ReadPly(path, bytes, req);
  m->xyz = std::move(d.xyz);
  m->tris = std::move(d.triangles);
  rep->polygons_triangulated += d.polygons_triangulated;
  for (auto& w : d.warnings) rep->warnings.push_back(std::move(w));
}

// ---- STL -------------------------------------------------------------------

struct PosKey {
  std::uint64_t b[3];
  bool operator==(const PosKey& o) const {
    return b[0] == o.b[0] && b[1] == o.b[1] && b[2] == o.b[2];
  }
};
struct PosKeyHash {
  std::size_t operator()(const PosKey& k) const {
    std::uint64_t h = 0x9E3779B97F4A7C15ull;
    for (std::uint64_t v : k.b) {
      h ^= v + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
      h *= 0xBF58476D1CE4E5B9ull;
    }
    return static_cast<std::size_t>(h ^ (h >> 31));
  }
};

// Merges bit-identical corner positions (+0 == -0) of a triangle soup;
// vertices are numbered in order of first use, so the result is deterministic.
void Weld(const std::vector<double>& corners, RawMesh* m, MeshReadReport* rep) {
  const std::size_t nc = corners.size() / 3;
  std::unordered_map<PosKey, int, PosKeyHash> index;
  index.reserve(nc);
  m->xyz.clear();
  m->tris.resize(nc);
  for (std::size_t c = 0; c < nc; ++c) {
    PosKey k;
    for (int a = 0; a < 3; ++a) {
      const double x = corners[3 * c + a] == 0.0 ? 0.0 : corners[3 * c + a];
      std::memcpy(&k.b[a], &x, sizeof(double));
    }
    const auto [it, inserted] = index.try_emplace(k, static_cast<int>(m->xyz.size() / 3));
    if (inserted) m->xyz.insert(m->xyz.end(), corners.begin() + 3 * c, corners.begin() + 3 * c + 3);
    m->tris[c] = it->second;
  }
  rep->welded_vertices += static_cast<int>(nc - m->xyz.size() / 3);
}

void ReadStlBinary(const std::string& path, std::string_view bytes, std::uint32_t n,
                   RawMesh* m, MeshReadReport* rep) {
  std::vector<double> corners;
  corners.reserve(9 * static_cast<std::size_t>(n));
  for (std::uint32_t t = 0; t < n; ++t) {
    const std::size_t base = 84 + 50 * static_cast<std::size_t>(t) + 12;  // skip the normal
    for (int c = 0; c < 9; ++c) {
      const float v = Load<float>(bytes.data() + base + 4 * c, true);
      if (!std::isfinite(v))
        ThrowAtOffset(path, base + 4 * c,
                      "triangle " + std::to_string(t) + " has a non-finite coordinate");
      corners.push_back(v);
    }
  }
  Weld(corners, m, rep);
}

void ReadStlAscii(const std::string& path, std::string_view text, RawMesh* m,
                  MeshReadReport* rep) {
  CheckIsText(path, text, "ASCII STL");
  LineReader lines(text);
  std::string_view line, kw, tok;
  std::vector<double> corners;
  std::vector<double> loop;  // coordinates of the current facet's vertices
  long loop_line = 0;
  auto close_loop = [&](long ln) {
    if (loop.empty()) return;
    const std::size_t nvl = loop.size() / 3;
    if (nvl < 3)
      ThrowAtLine(path, ln,
                  "facet has " + std::to_string(nvl) + " vertices (a facet needs at least 3)");
    if (nvl > 3) ++rep->polygons_triangulated;
    for (std::size_t k = 1; k + 1 < nvl; ++k) {
      for (std::size_t c : {std::size_t{0}, k, k + 1})
        corners.insert(corners.end(), loop.begin() + 3 * c, loop.begin() + 3 * c + 3);
    }
    loop.clear();
  };
  while (lines.Next(&line)) {
    Tokenizer tk(line);
    if (!tk.Next(&kw)) continue;
    const long ln = lines.line();
    if (EqualsIgnoreCase(kw, "vertex")) {
      if (loop.empty()) loop_line = ln;
      int k = 0;
      for (; k < 3 && tk.Next(&tok); ++k) {
        double v = 0;
        const NumStatus st = ParseDouble(tok, &v);
        if (st != NumStatus::kOk) ThrowAtLine(path, ln, "bad vertex coordinate " + Quote(tok));
        if (!std::isfinite(v)) ThrowAtLine(path, ln, "non-finite vertex coordinate " + Quote(tok));
        loop.push_back(v);
      }
      if (k < 3)
        ThrowAtLine(path, ln, "vertex has " + std::to_string(k) + " coordinates, expected 3");
    } else if (EqualsIgnoreCase(kw, "endloop") || EqualsIgnoreCase(kw, "endfacet")) {
      close_loop(ln);
    } else if (EqualsIgnoreCase(kw, "facet") || EqualsIgnoreCase(kw, "outer") ||
               EqualsIgnoreCase(kw, "solid") || EqualsIgnoreCase(kw, "endsolid")) {
      if (!loop.empty())
        ThrowAtLine(path, ln, "facet starting at line " + std::to_string(loop_line) +
                                  " is not closed by 'endloop'");
    } else {
      ThrowAtLine(path, ln, "unexpected " + Quote(kw) + " in an ASCII STL file");
    }
  }
  if (!loop.empty())
    ThrowAtLine(path, lines.line(), "unexpected end of file inside the facet starting at line " +
                                        std::to_string(loop_line));
  Weld(corners, m, rep);
}

void ReadStl(const std::string& path, std::string_view bytes, RawMesh* m, MeshReadReport* rep) {
  std::size_t i = bytes.substr(0, 3) == "\xEF\xBB\xBF" ? 3 : 0;  // a UTF-8 byte-order mark
  while (i < bytes.size() && (IsSpace(bytes[i]) || bytes[i] == '\n')) ++i;
  const bool solid = bytes.size() - i >= 5 && EqualsIgnoreCase(bytes.substr(i, 5), "solid");
  if (bytes.size() >= 84) {
    const std::uint32_t n = Load<std::uint32_t>(bytes.data() + 80, true);
    const std::uint64_t expect = 84 + 50 * static_cast<std::uint64_t>(n);
    if (n > static_cast<std::uint32_t>(INT_MAX / 3) && bytes.size() >= expect)
      ThrowAtOffset(path, 80, "more than 2^31 / 3 triangles");
    // The size test decides: many binary STLs start with "solid" too.
    if (bytes.size() == expect) return ReadStlBinary(path, bytes, n, m, rep);
    if (!solid) {
      if (bytes.size() < expect)
        ThrowAtOffset(path, 80,
                      "binary STL header says " + std::to_string(n) + " triangles (" +
                          std::to_string(expect) + " bytes) but the file has only " +
                          std::to_string(bytes.size()) + " bytes");
      rep->warnings.push_back(std::to_string(bytes.size() - expect) +
                              " bytes after the last STL triangle ignored");
      return ReadStlBinary(path, bytes, n, m, rep);
    }
    if (std::memchr(bytes.data(), '\0', bytes.size()))
      ThrowAtOffset(path, 80,
                    "file starts with 'solid' but holds binary data, and its size (" +
                        std::to_string(bytes.size()) + " bytes) does not match a binary STL of " +
                        std::to_string(n) + " triangles (" + std::to_string(expect) +
                        " bytes): truncated?");
    return ReadStlAscii(path, bytes, m, rep);
  }
  if (solid) return ReadStlAscii(path, bytes, m, rep);
  ThrowAtOffset(path, 0,
                "not an STL file: too short for binary STL (" + std::to_string(bytes.size()) +
                    " bytes < 84) and no 'solid' keyword");
}

// ---- common ----------------------------------------------------------------

Mesh Finish(RawMesh&& raw, MeshReadReport* rep) {
  const std::size_t nv = raw.xyz.size() / 3, nt = raw.tris.size() / 3;
  Mesh mesh;
  mesh.V.resize(static_cast<Eigen::Index>(nv), 3);
  mesh.F.resize(static_cast<Eigen::Index>(nt), 3);
  if (nv) std::memcpy(mesh.V.data(), raw.xyz.data(), raw.xyz.size() * sizeof(double));
  if (nt) std::memcpy(mesh.F.data(), raw.tris.data(), raw.tris.size() * sizeof(int));
  std::vector<char> used(nv, 0);
  for (std::size_t t = 0; t < nt; ++t) {
    const int a = raw.tris[3 * t], b = raw.tris[3 * t + 1], c = raw.tris[3 * t + 2];
    used[a] = used[b] = used[c] = 1;
    if (a == b || b == c || a == c) ++rep->degenerate_faces;
  }
  for (char u : used) rep->unreferenced_vertices += u ? 0 : 1;
  auto note = [&](int count, const char* what) {
    if (count > 0) rep->warnings.push_back(std::to_string(count) + " " + what);
  };
  if (nv == 0) rep->warnings.push_back("the file has no vertices");
  if (nv > 0 && nt == 0) rep->warnings.push_back("the file has no faces");
  note(rep->polygons_triangulated, "polygons fan-triangulated");
  note(rep->rational_coordinates, "coordinates given as exact rationals p/q");
  note(rep->welded_vertices, "STL corners welded onto equal positions");
  note(rep->unreferenced_vertices, "unreferenced vertices (kept)");
  note(rep->degenerate_faces, "degenerate faces with a repeated vertex (kept)");
  return mesh;
}

// ---- writers ---------------------------------------------------------------

void CheckWritable(const std::string& path, const Mesh& mesh) {
  if (!mesh.V.allFinite()) throw Error("cannot write '" + path + "': non-finite vertex coordinates");
  const int nv = mesh.NumVertices();
  for (int f = 0; f < mesh.NumFaces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      if (mesh.F(f, k) < 0 || mesh.F(f, k) >= nv)
        throw Error("cannot write '" + path + "': face " + std::to_string(f) +
                    " has vertex index " + std::to_string(mesh.F(f, k)) + " out of range [0, " +
                    std::to_string(nv) + ")");
    }
  }
}

std::string ObjText(const Mesh& mesh) {
  std::string s;
  s.reserve(static_cast<std::size_t>(mesh.NumVertices()) * 60 + mesh.NumFaces() * 24 + 64);
  s += "# written by arcs: " + std::to_string(mesh.NumVertices()) + " vertices, " +
       std::to_string(mesh.NumFaces()) + " triangles\n";
  for (int v = 0; v < mesh.NumVertices(); ++v) {
    s += "v";
    for (int a = 0; a < 3; ++a) {
      s += ' ';
      AppendDouble(&s, mesh.V(v, a));
    }
    s += '\n';
  }
  for (int f = 0; f < mesh.NumFaces(); ++f) {
    s += "f";
    for (int k = 0; k < 3; ++k) {
      s += ' ';
      AppendInt(&s, mesh.F(f, k) + 1);
    }
    s += '\n';
  }
  return s;
}

std::string OffText(const Mesh& mesh) {
  std::string s;
  s.reserve(static_cast<std::size_t>(mesh.NumVertices()) * 60 + mesh.NumFaces() * 24 + 64);
  s += "OFF\n" + std::to_string(mesh.NumVertices()) + " " + std::to_string(mesh.NumFaces()) +
       " 0\n";
  for (int v = 0; v < mesh.NumVertices(); ++v) {
    for (int a = 0; a < 3; ++a) {
      if (a) s += ' ';
      AppendDouble(&s, mesh.V(v, a));
    }
    s += '\n';
  }
  for (int f = 0; f < mesh.NumFaces(); ++f) {
    s += "3";
    for (int k = 0; k < 3; ++k) {
      s += ' ';
      AppendInt(&s, mesh.F(f, k));
    }
    s += '\n';
  }
  return s;
}

std::string PlyBytes(const Mesh& mesh) {
  std::string s =
      "ply\nformat binary_little_endian 1.0\ncomment written by arcs\nelement vertex " +
      std::to_string(mesh.NumVertices()) +
      "\nproperty double x\nproperty double y\nproperty double z\nelement face " +
      std::to_string(mesh.NumFaces()) + "\nproperty list uchar int vertex_indices\nend_header\n";
  s.reserve(s.size() + static_cast<std::size_t>(mesh.NumVertices()) * 24 + mesh.NumFaces() * 13);
  for (int v = 0; v < mesh.NumVertices(); ++v) {
    for (int a = 0; a < 3; ++a) AppendLE<double>(&s, mesh.V(v, a));
  }
  for (int f = 0; f < mesh.NumFaces(); ++f) {
    s += static_cast<char>(3);
    for (int k = 0; k < 3; ++k) AppendLE<std::int32_t>(&s, mesh.F(f, k));
  }
  return s;
}

std::string StlBytes(const std::string& path, const Mesh& mesh) {
  std::string s(80, ' ');
  const char kHeader[] = "binary STL written by arcs";  // must not start with "solid"
  std::memcpy(s.data(), kHeader, sizeof(kHeader) - 1);
  AppendLE<std::uint32_t>(&s, static_cast<std::uint32_t>(mesh.NumFaces()));
  s.reserve(84 + 50 * static_cast<std::size_t>(mesh.NumFaces()));
  for (int f = 0; f < mesh.NumFaces(); ++f) {
    const Vec3 a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)),
               c = mesh.V.row(mesh.F(f, 2));
    const Vec3 u = b - a, w = c - a;
    Vec3 n(u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]);
    const double len = n.norm();
    n = len > 0 ? Vec3(n / len) : Vec3::Zero();
    for (int k = 0; k < 3; ++k) AppendLE<float>(&s, static_cast<float>(n[k]));
    for (const Vec3* p : {&a, &b, &c}) {
      for (int k = 0; k < 3; ++k) {
        const float x = static_cast<float>((*p)[k]);
        if (!std::isfinite(x))
          throw Error("cannot write '" + path + "': coordinate " + FormatDouble((*p)[k]) +
                      " exceeds the float range of STL");
        AppendLE<float>(&s, x);
      }
    }
    AppendLE<std::uint16_t>(&s, 0);
  }
  return s;
}

}  // namespace

std::string SupportedMeshExtensions() { return ".obj .off .ply .stl"; }

Mesh ReadMesh(const std::string& path, MeshReadReport* report) {
  const std::string ext = LowerExtension(path);
  if (ext != ".obj" && ext != ".off" && ext != ".ply" && ext != ".stl")
    throw InputError(path, 0,
                     "unsupported mesh format '" + ext + "' (supported: " +
                         SupportedMeshExtensions() + ")");
  MeshReadReport local;
  MeshReadReport* rep = report ? report : &local;
  *rep = MeshReadReport();
  const FileBytes file = ReadWholeFile(path);
  const std::string_view bytes = file.view();
  RawMesh raw;
  if (ext == ".obj") {
    ReadObj(path, bytes, &raw, rep);
  } else if (ext == ".off") {
    ReadOff(path, bytes, &raw, rep);
  } else if (ext == ".ply") {
    ReadPlyMesh(path, bytes, &raw, rep);
  } else {
    ReadStl(path, bytes, &raw, rep);
  }
  return Finish(std::move(raw), rep);
}

void WriteMesh(const std::string& path, const Mesh& mesh) {
  const std::string ext = LowerExtension(path);
  if (ext != ".obj" && ext != ".off" && ext != ".ply" && ext != ".stl")
    throw InputError(path, 0,
                     "unsupported mesh format '" + ext + "' for writing (supported: " +
                         SupportedMeshExtensions() + ")");
  CheckWritable(path, mesh);
  if (ext == ".obj") {
    WriteWholeFile(path, ObjText(mesh));
  } else if (ext == ".off") {
    WriteWholeFile(path, OffText(mesh));
  } else if (ext == ".ply") {
    WriteWholeFile(path, PlyBytes(mesh));
  } else {
    WriteWholeFile(path, StlBytes(path, mesh));
  }
}

}  // namespace arcs
