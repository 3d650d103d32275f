#include "framework/io/ply.h"

#include "framework/io/io_util.h"

#include <algorithm>
#include <climits>
#include <cmath>

namespace arcs::io_internal {
namespace {

enum class PType : std::uint8_t { kI8, kU8, kI16, kU16, kI32, kU32, kF32, kF64 };

int TypeSize(PType t) {
  switch (t) {
    case PType::kI8:
    case PType::kU8: return 1;
    case PType::kI16:
    case PType::kU16: return 2;
    case PType::kI32:
    case PType::kU32:
    case PType::kF32: return 4;
    case PType::kF64: return 8;
  }
  return 1;
}

bool IsIntegerType(PType t) { return t != PType::kF32 && t != PType::kF64; }

bool ParseType(std::string_view s, PType* t) {
  struct Name {
    const char* name;
    PType type;
  };
  static const Name kNames[] = {
      {"char", PType::kI8},    {"int8", PType::kI8},      {"uchar", PType::kU8},
      {"uint8", PType::kU8},   {"short", PType::kI16},    {"int16", PType::kI16},
      {"ushort", PType::kU16}, {"uint16", PType::kU16},   {"int", PType::kI32},
      {"int32", PType::kI32},  {"uint", PType::kU32},     {"uint32", PType::kU32},
      {"float", PType::kF32},  {"float32", PType::kF32},  {"double", PType::kF64},
      {"float64", PType::kF64}};
  for (const Name& n : kNames) {
    if (s == n.name) {
      *t = n.type;
      return true;
    }
  }
  return false;
}

double LoadDouble(const char* p, PType t, bool le) {
  switch (t) {
    case PType::kI8: return static_cast<double>(static_cast<std::int8_t>(*p));
    case PType::kU8: return static_cast<double>(static_cast<std::uint8_t>(*p));
    case PType::kI16: return Load<std::int16_t>(p, le);
    case PType::kU16: return Load<std::uint16_t>(p, le);
    case PType::kI32: return Load<std::int32_t>(p, le);
    case PType::kU32: return Load<std::uint32_t>(p, le);
    case PType::kF32: return Load<float>(p, le);
    case PType::kF64: return Load<double>(p, le);
  }
  return 0;
}

// Integer types only (checked when the header is parsed).
std::int64_t LoadInt(const char* p, PType t, bool le) {
  switch (t) {
    case PType::kI8: return static_cast<std::int8_t>(*p);
    case PType::kU8: return static_cast<std::uint8_t>(*p);
    case PType::kI16: return Load<std::int16_t>(p, le);
    case PType::kU16: return Load<std::uint16_t>(p, le);
    case PType::kI32: return Load<std::int32_t>(p, le);
    case PType::kU32: return Load<std::uint32_t>(p, le);
    default: return 0;
  }
}

struct Prop {
  std::string name;
  bool list = false;
  PType type = PType::kF32;        // scalar type, or list item type
  PType count_type = PType::kU8;   // list count type
};

struct Elem {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Prop> props;
  long line = 0;  // header line declaring the element
};

enum class Format { kAscii, kBinaryLE, kBinaryBE };

struct Header {
  Format format = Format::kAscii;
  std::vector<Elem> elements;
  std::size_t body_offset = 0;
  long body_line = 0;  // first line of the body (ASCII)
};

std::string StripCR(std::string_view line) {
  while (!line.empty() && IsSpace(line.back())) line.remove_suffix(1);
  return std::string(line);
}

Header ParseHeader(const std::string& path, std::string_view bytes) {
  Header h;
  LineReader lines(bytes);
  std::string_view line;
  if (!lines.Next(&line) || StripCR(line) != "ply")
    ThrowAtLine(path, 1, "not a PLY file: the first line must be 'ply'");
  bool have_format = false;
  for (;;) {
    if (!lines.Next(&line))
      ThrowAtLine(path, lines.line(), "PLY header has no 'end_header' line");
    const long ln = lines.line();
    if (line.find('\0') != std::string_view::npos)
      ThrowAtLine(path, ln, "binary data inside the PLY header (missing 'end_header'?)");
    Tokenizer tk(line);
    std::string_view kw;
    if (!tk.Next(&kw)) continue;
    if (kw == "comment" || kw == "obj_info") continue;
    if (kw == "end_header") {
      h.body_offset = lines.offset();
      h.body_line = ln + 1;
      break;
    }
    if (kw == "format") {
      std::string_view f;
      if (!tk.Next(&f)) ThrowAtLine(path, ln, "'format' needs a value");
      if (f == "ascii") {
        h.format = Format::kAscii;
      } else if (f == "binary_little_endian") {
        h.format = Format::kBinaryLE;
      } else if (f == "binary_big_endian") {
        h.format = Format::kBinaryBE;
      } else {
        ThrowAtLine(path, ln,
                    "unknown PLY format " + Quote(f) +
                        " (expected ascii, binary_little_endian or binary_big_endian)");
      }
      have_format = true;
      continue;
    }
    if (kw == "element") {
      std::string_view name, count;
      if (!tk.Next(&name) || !tk.Next(&count))
        ThrowAtLine(path, ln, "'element' needs a name and a count");
      std::int64_t c = 0;
      if (ParseInt64(count, &c) != NumStatus::kOk || c < 0)
        ThrowAtLine(path, ln, "bad element count " + Quote(count));
      Elem e;
      e.name = std::string(name);
      e.count = static_cast<std::uint64_t>(c);
      e.line = ln;
      h.elements.push_back(std::move(e));
      continue;
    }
    if (kw == "property") {
      if (h.elements.empty()) ThrowAtLine(path, ln, "'property' before any 'element'");
      Prop p;
      std::string_view t, name;
      if (!tk.Next(&t)) ThrowAtLine(path, ln, "'property' needs a type and a name");
      if (t == "list") {
        std::string_view ct, it;
        if (!tk.Next(&ct) || !tk.Next(&it) || !tk.Next(&name))
          ThrowAtLine(path, ln, "'property list' needs a count type, an item type and a name");
        p.list = true;
        if (!ParseType(ct, &p.count_type)) ThrowAtLine(path, ln, "unknown PLY type " + Quote(ct));
        if (!IsIntegerType(p.count_type))
          ThrowAtLine(path, ln, "list count type must be an integer type, not " + Quote(ct));
        if (!ParseType(it, &p.type)) ThrowAtLine(path, ln, "unknown PLY type " + Quote(it));
      } else {
        if (!tk.Next(&name)) ThrowAtLine(path, ln, "'property' needs a type and a name");
        if (!ParseType(t, &p.type)) ThrowAtLine(path, ln, "unknown PLY type " + Quote(t));
      }
      p.name = std::string(name);
      h.elements.back().props.push_back(std::move(p));
      continue;
    }
    ThrowAtLine(path, ln, "unknown PLY header keyword " + Quote(kw));
  }
  if (!have_format) ThrowAtLine(path, 2, "PLY header has no 'format' line");
  return h;
}

int FindProp(const Elem& e, std::string_view a, std::string_view b = {}) {
  for (std::size_t i = 0; i < e.props.size(); ++i) {
    if (e.props[i].name == a || (!b.empty() && e.props[i].name == b)) return static_cast<int>(i);
  }
  return -1;
}

// What the reader does with each property of an element.
enum class Role : std::uint8_t { kSkip, kX, kY, kZ, kNX, kNY, kNZ, kFace };

struct Reader {
  const std::string& path;
  std::string_view bytes;
  const Header& h;
  const PlyRequest& req;
  PlyData& out;
  std::int64_t num_vertices = 0;

  std::vector<std::int64_t> poly;  // reused polygon buffer

  std::string Where(const Elem& e, std::uint64_t i) const {
    return "element '" + e.name + "' entry " + std::to_string(i) + " of " +
           std::to_string(e.count);
  }

  std::vector<Role> Roles(const Elem& e, bool is_vertex, bool is_face) {
    std::vector<Role> roles(e.props.size(), Role::kSkip);
    if (is_vertex) {
      const int ix = FindProp(e, "x"), iy = FindProp(e, "y"), iz = FindProp(e, "z");
      if (ix < 0 || iy < 0 || iz < 0)
        ThrowAtLine(path, e.line, "the vertex element needs properties x, y and z");
      for (int i : {ix, iy, iz}) {
        if (e.props[i].list)
          ThrowAtLine(path, e.line, "vertex property '" + e.props[i].name + "' is a list");
      }
      roles[ix] = Role::kX;
      roles[iy] = Role::kY;
      roles[iz] = Role::kZ;
      if (req.want_normals) {
        int inx = FindProp(e, "nx", "normal_x"), iny = FindProp(e, "ny", "normal_y"),
            inz = FindProp(e, "nz", "normal_z");
        if (inx >= 0 && iny >= 0 && inz >= 0 && !e.props[inx].list && !e.props[iny].list &&
            !e.props[inz].list) {
          roles[inx] = Role::kNX;
          roles[iny] = Role::kNY;
          roles[inz] = Role::kNZ;
          out.has_normals = true;
        } else if (inx >= 0 || iny >= 0 || inz >= 0) {
          out.warnings.push_back("incomplete vertex normals (need nx, ny, nz): ignored");
        }
      }
    }
    if (is_face) {
      const int iv = FindProp(e, "vertex_indices", "vertex_index");
      if (iv < 0 || !e.props[iv].list)
        ThrowAtLine(path, e.line,
                    "the face element needs a list property 'vertex_indices' (or "
                    "'vertex_index')");
      if (!IsIntegerType(e.props[iv].type))
        ThrowAtLine(path, e.line, "face vertex indices must have an integer type");
      roles[iv] = Role::kFace;
      out.has_faces = true;
    }
    return roles;
  }

  // Checks the claimed count of a binary element against the bytes left,
  // before any allocation (each entry needs at least its scalars and list
  // counts).
  void CheckCount(const Elem& e, std::size_t remaining) {
    std::uint64_t min_bytes = 0;
    for (const Prop& p : e.props) {
      min_bytes += static_cast<std::uint64_t>(TypeSize(p.list ? p.count_type : p.type));
    }
    if (min_bytes == 0) return;
    if (e.count > (static_cast<std::uint64_t>(remaining) + 1) / min_bytes) {
      ThrowAtLine(path, e.line,
                  "element '" + e.name + "' claims " + std::to_string(e.count) +
                      " entries of at least " + std::to_string(min_bytes) +
                      " bytes each, but only " + std::to_string(remaining) +
                      " bytes follow the header");
    }
  }

  void AddPolygon(const Elem& e, std::uint64_t i, const std::vector<std::int64_t>& idx,
                  bool binary, std::uint64_t location) {
    auto fail = [&](const std::string& what) {
      if (binary) ThrowAtOffset(path, location, what);
      ThrowAtLine(path, static_cast<long>(location), what);
    };
    if (idx.size() < 3)
      fail("face " + std::to_string(i) + " has " + std::to_string(idx.size()) +
           " vertices (a face needs at least 3)");
    for (std::int64_t v : idx) {
      if (v < 0 || v >= num_vertices)
        fail("face " + std::to_string(i) + " has vertex index " + std::to_string(v) +
             " out of range [0, " + std::to_string(num_vertices) + ")");
    }
    if (idx.size() > 3) ++out.polygons_triangulated;
    for (std::size_t k = 1; k + 1 < idx.size(); ++k) {
      out.triangles.push_back(static_cast<int>(idx[0]));
      out.triangles.push_back(static_cast<int>(idx[k]));
      out.triangles.push_back(static_cast<int>(idx[k + 1]));
    }
    if (out.triangles.size() / 3 > static_cast<std::size_t>(INT_MAX))
      fail("more than 2^31 triangles");
  }

  void StoreVertex(const double* vals, std::uint64_t i, bool binary, std::uint64_t location) {
    const bool finite = std::isfinite(vals[0]) && std::isfinite(vals[1]) &&
                        std::isfinite(vals[2]) &&
                        (!out.has_normals || (std::isfinite(vals[3]) && std::isfinite(vals[4]) &&
                                              std::isfinite(vals[5])));
    if (!finite) {
      if (req.nonfinite_is_error) {
        const std::string what = "vertex " + std::to_string(i) + " has a non-finite coordinate";
        if (binary) ThrowAtOffset(path, location, what);
        ThrowAtLine(path, static_cast<long>(location), what);
      }
      out.nonfinite.push_back({static_cast<std::int64_t>(i), location});
    }
    out.xyz.insert(out.xyz.end(), vals, vals + 3);
    if (out.has_normals) out.normals.insert(out.normals.end(), vals + 3, vals + 6);
  }

  // An element without properties holds nothing: its entries are skipped at
  // once (no loop over the count), and a count beyond the bytes that follow
  // is a lying header, refused like any other.
  bool SkipEmptyElement(const Elem& e, std::size_t remaining) {
    if (!e.props.empty()) return false;
    if (e.count > static_cast<std::uint64_t>(remaining))
      ThrowAtLine(path, e.line,
                  "element '" + e.name + "' has no properties but claims " + std::to_string(e.count) +
                      " entries, more than the " + std::to_string(remaining) + " bytes after the header");
    return true;
  }

  void ReadBinaryElement(const Elem& e, std::size_t* pos, bool le, bool is_vertex, bool is_face) {
    CheckCount(e, bytes.size() - *pos);
    const std::vector<Role> roles = Roles(e, is_vertex, is_face);  // the vertex element needs x y z
    if (SkipEmptyElement(e, bytes.size() - *pos)) return;
    if (is_vertex) {
      out.xyz.reserve(3 * e.count);
      if (out.has_normals) out.normals.reserve(3 * e.count);
    }
    if (is_face) {
      // Room for one triangle per face, as many as the bytes left can hold.
      for (std::size_t k = 0; k < e.props.size(); ++k) {
        if (roles[k] != Role::kFace) continue;
        const std::size_t tri_bytes = TypeSize(e.props[k].count_type) + 3 * TypeSize(e.props[k].type);
        out.triangles.reserve(
            3 * std::min<std::uint64_t>(e.count, (bytes.size() - *pos) / tri_bytes + 1));
      }
    }
    const char* base = bytes.data();
    const std::size_t size = bytes.size();
    for (std::uint64_t i = 0; i < e.count; ++i) {
      const std::size_t start = *pos;
      double vals[6] = {0, 0, 0, 0, 0, 0};
      for (std::size_t k = 0; k < e.props.size(); ++k) {
        const Prop& p = e.props[k];
        if (!p.list) {
          const std::size_t ts = TypeSize(p.type);
          if (size - *pos < ts)
            ThrowAtOffset(path, *pos, "unexpected end of file in " + Where(e, i));
          if (roles[k] != Role::kSkip)
            vals[static_cast<int>(roles[k]) - 1] = LoadDouble(base + *pos, p.type, le);
          *pos += ts;
          continue;
        }
        const std::size_t cs = TypeSize(p.count_type);
        if (size - *pos < cs) ThrowAtOffset(path, *pos, "unexpected end of file in " + Where(e, i));
        const std::int64_t n = LoadInt(base + *pos, p.count_type, le);
        if (n < 0)
          ThrowAtOffset(path, *pos, "negative list length " + std::to_string(n) + " in " + Where(e, i));
        const std::size_t list_pos = *pos;
        *pos += cs;
        const std::size_t is = TypeSize(p.type);
        if (static_cast<std::uint64_t>(n) > (size - *pos) / is)
          ThrowAtOffset(path, list_pos,
                        "list of " + std::to_string(n) + " items runs past the end of file in " +
                            Where(e, i));
        if (roles[k] == Role::kFace) {
          poly.resize(static_cast<std::size_t>(n));
          for (std::int64_t j = 0; j < n; ++j) poly[j] = LoadInt(base + *pos + j * is, p.type, le);
          AddPolygon(e, i, poly, true, start);
        }
        *pos += static_cast<std::size_t>(n) * is;
      }
      if (is_vertex) StoreVertex(vals, i, true, start);
    }
  }

  void ReadAsciiElement(const Elem& e, TokenStream* ts, bool is_vertex, bool is_face) {
    const std::vector<Role> roles = Roles(e, is_vertex, is_face);  // the vertex element needs x y z
    if (SkipEmptyElement(e, ts->remaining())) return;
    if (is_vertex) {
      // The count is not trusted for allocation: an entry needs >= 2 bytes per
      // property, so a lying header reserves at most what the file could
      // hold, and a short file fails at the line where its data runs out.
      const std::uint64_t plausible =
          (ts->remaining() + 1) / (2 * std::max<std::size_t>(1, e.props.size())) + 1;
      const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(e.count, plausible));
      out.xyz.reserve(3 * n);
      if (out.has_normals) out.normals.reserve(3 * n);
    }
    if (is_face) {  // a triangle line "3 a b c\n" needs >= 8 bytes
      out.triangles.reserve(3 * std::min<std::uint64_t>(e.count, ts->remaining() / 8 + 1));
    }
    std::string_view tok;
    for (std::uint64_t i = 0; i < e.count; ++i) {
      double vals[6] = {0, 0, 0, 0, 0, 0};
      long start_line = 0;
      auto next = [&]() {
        if (!ts->Next(&tok))
          ThrowAtLine(path, ts->line(), "unexpected end of file in " + Where(e, i));
      };
      for (std::size_t k = 0; k < e.props.size(); ++k) {
        const Prop& p = e.props[k];
        next();
        if (k == 0) start_line = ts->line();
        if (!p.list) {
          if (roles[k] != Role::kSkip) {
            double v = 0;
            const NumStatus st = ParseDouble(tok, &v);
            if (st != NumStatus::kOk)
              ThrowAtLine(path, ts->line(),
                          "bad number " + Quote(tok) + " for property '" + p.name + "' in " +
                              Where(e, i));
            vals[static_cast<int>(roles[k]) - 1] = v;
          }
          continue;
        }
        std::int64_t n = 0;
        if (ParseInt64(tok, &n) != NumStatus::kOk || n < 0)
          ThrowAtLine(path, ts->line(),
                      "bad list length " + Quote(tok) + " in " + Where(e, i));
        if (roles[k] == Role::kFace) {
          poly.clear();
          for (std::int64_t j = 0; j < n; ++j) {
            next();
            std::int64_t v = 0;
            if (ParseInt64(tok, &v) != NumStatus::kOk)
              ThrowAtLine(path, ts->line(), "bad vertex index " + Quote(tok) + " in " + Where(e, i));
            poly.push_back(v);
          }
          AddPolygon(e, i, poly, false, static_cast<std::uint64_t>(ts->line()));
        } else {
          for (std::int64_t j = 0; j < n; ++j) next();
        }
      }
      if (is_vertex) StoreVertex(vals, i, false, static_cast<std::uint64_t>(start_line));
    }
  }
};

}  // namespace

PlyData ReadPly(const std::string& path, std::string_view bytes, const PlyRequest& request) {
  const Header h = ParseHeader(path, bytes);
  PlyData out;
  out.binary = h.format != Format::kAscii;
  Reader r{path, bytes, h, request, out, 0, {}};

  const Elem* vertex = nullptr;
  for (const Elem& e : h.elements) {
    if (e.name == "vertex") {
      if (vertex) ThrowAtLine(path, e.line, "more than one 'vertex' element");
      vertex = &e;
    }
  }
  if (!vertex) ThrowAtLine(path, 0, "PLY file has no 'vertex' element");
  if (vertex->count > static_cast<std::uint64_t>(INT_MAX))
    ThrowAtLine(path, vertex->line, "more than 2^31 vertices");
  r.num_vertices = static_cast<std::int64_t>(vertex->count);
  out.num_vertices = r.num_vertices;

  bool seen_face = false;
  if (out.binary) {
    std::size_t pos = h.body_offset;
    const bool le = h.format == Format::kBinaryLE;
    for (const Elem& e : h.elements) {
      const bool is_vertex = &e == vertex;
      const bool is_face = request.want_faces && e.name == "face" && !seen_face;
      seen_face = seen_face || is_face;
      r.ReadBinaryElement(e, &pos, le, is_vertex, is_face);
    }
  } else {
    TokenStream ts(bytes.substr(h.body_offset), h.body_line);
    for (const Elem& e : h.elements) {
      const bool is_vertex = &e == vertex;
      const bool is_face = request.want_faces && e.name == "face" && !seen_face;
      seen_face = seen_face || is_face;
      r.ReadAsciiElement(e, &ts, is_vertex, is_face);
    }
    std::string_view extra;
    if (ts.Next(&extra))
      out.warnings.push_back("data after the last PLY element (from line " +
                             std::to_string(ts.line()) + ") ignored");
  }
  for (const Elem& e : h.elements) {
    if (e.name != "vertex" && e.name != "face" && e.count > 0)
      out.warnings.push_back("PLY element '" + e.name + "' (" + std::to_string(e.count) +
                             " entries) ignored");
  }
  return out;
}

}  // namespace arcs::io_internal
