#include "framework/io/sdf_io.h"

#include "framework/io/io_util.h"
#include "framework/io/npy.h"
#include "framework/io/npz.h"

#include <climits>
#include <cmath>
#include <filesystem>

namespace arcs {
namespace {

using namespace io_internal;


bool FileExists(const std::string& path) {
  std::error_code ec;
  return std::filesystem::is_regular_file(path, ec);
}

// Reads "xmin ymin [zmin] xmax ymax [zmax]" from a bounds sidecar.
void ReadBounds(const std::string& path, int dim, std::array<double, 3>* min,
                std::array<double, 3>* max) {
  const FileBytes file = ReadWholeFile(path);
  const std::string_view text = file.view();
  CheckIsText(path, text, "bounds");
  LineReader lines(text);
  std::string_view line, tok;
  std::vector<double> v;
  while (lines.Next(&line)) {
    Tokenizer tk(StripComment(line));
    while (tk.Next(&tok)) {
      double x = 0;
      if (ParseDouble(tok, &x) != NumStatus::kOk || !std::isfinite(x))
        ThrowAtLine(path, lines.line(), "bad bound " + Quote(tok) + " (need a finite number)");
      if (static_cast<int>(v.size()) == 2 * dim)
        ThrowAtLine(path, lines.line(),
                    "too many numbers: a " + std::to_string(dim) + "D grid needs " +
                        std::to_string(2 * dim) + (dim == 3 ? " (xmin ymin zmin xmax ymax zmax)"
                                                            : " (xmin ymin xmax ymax)"));
      v.push_back(x);
    }
  }
  if (static_cast<int>(v.size()) != 2 * dim)
    ThrowAtLine(path, 0,
                "found " + std::to_string(v.size()) + " numbers, a " + std::to_string(dim) +
                    "D grid needs " + std::to_string(2 * dim) +
                    (dim == 3 ? " (xmin ymin zmin xmax ymax zmax)" : " (xmin ymin xmax ymax)"));
  *min = {0, 0, 0};
  *max = {0, 0, 0};
  for (int a = 0; a < dim; ++a) {
    (*min)[a] = v[a];
    (*max)[a] = v[dim + a];
  }
}

// numpy.linspace(lo, hi, n)[i], bit for bit: i * step + lo, last node = hi.
double Linspace(double lo, double hi, int n, int i) {
  if (n > 1 && i == n - 1) return hi;
  if (n <= 1) return lo;
  const double step = (hi - lo) / (n - 1);
  return static_cast<double>(i) * step + lo;
}

}  // namespace

SdfSamples SdfGridFromArray(const std::string& path, const NpyArray& arr, std::array<double, 3> min,
                            std::array<double, 3> max, const std::string& bounds_origin) {
  const int dim = arr.Ndim();
  if (dim != 2 && dim != 3)
    throw InputError(path, 0,
                     "grid values must have shape (nx, ny, nz) or (nx, ny), got " +
                         NpyShapeString(arr.shape));
  for (std::int64_t d : arr.shape) {
    if (d < 1 || d > INT_MAX)
      throw InputError(path, 0, "grid shape " + NpyShapeString(arr.shape) + " has an empty or huge axis");
  }
  if (dim == 2) {
    min[2] = max[2] = 0;
  }
  for (int a = 0; a < dim; ++a) {
    if (!std::isfinite(min[a]) || !std::isfinite(max[a]) || !(min[a] < max[a]))
      throw InputError(path, 0,
                       "grid bounds from " + bounds_origin + " need finite min < max on axis " +
                           std::to_string(a) + ", got [" + FormatDouble(min[a]) + ", " +
                           FormatDouble(max[a]) + "]");
  }
  const int nx = static_cast<int>(arr.shape[0]), ny = static_cast<int>(arr.shape[1]),
            nz = dim == 3 ? static_cast<int>(arr.shape[2]) : 1;
  SdfSamples s;
  s.dim = dim;
  GridInfo g;
  g.dim = dim;
  g.dims = {nx, ny, nz};
  g.min = min;
  g.max = max;
  const std::int64_t n = g.NumNodes();
  s.points.resize(n, dim);
  s.values.resize(n);
  for (int i = 0; i < nx; ++i) {
    const double x = Linspace(min[0], max[0], nx, i);
    for (int j = 0; j < ny; ++j) {
      const double y = Linspace(min[1], max[1], ny, j);
      for (int k = 0; k < nz; ++k) {
        // numpy C order in, arcs order (x fastest) out.
        const std::int64_t src = (static_cast<std::int64_t>(i) * ny + j) * nz + k;
        const std::int64_t dst = i + static_cast<std::int64_t>(nx) * (j + static_cast<std::int64_t>(ny) * k);
        const double v = arr.data[src];
        if (!std::isfinite(v))
          throw InputError(path, 0,
                           "value at grid index (" + std::to_string(i) + ", " + std::to_string(j) +
                               (dim == 3 ? ", " + std::to_string(k) : std::string()) +
                               ") is not finite (" + FormatDouble(v) + ")");
        s.values[dst] = v;
        s.points(dst, 0) = x;
        s.points(dst, 1) = y;
        if (dim == 3) s.points(dst, 2) = Linspace(min[2], max[2], nz, k);
      }
    }
  }
  s.grid = g;
  return s;
}

namespace {

SdfSamples GridFromArray(const std::string& path, const NpyArray& arr, std::array<double, 3> min,
                         std::array<double, 3> max) {
  const std::string sidecar = SdfBoundsPath(path);
  if (FileExists(sidecar) && (arr.Ndim() == 2 || arr.Ndim() == 3)) {
    ReadBounds(sidecar, arr.Ndim(), &min, &max);
    return SdfGridFromArray(path, arr, min, max, sidecar);
  }
  return SdfGridFromArray(path, arr, min, max);
}

// Samples from columns: points = first `dim` columns of P, values V.
SdfSamples FromColumns(const std::string& ppath, const NpyArray& P, int dim,
                       std::int64_t pstride, const std::string& vpath, const double* values,
                       std::int64_t vstride, std::int64_t n, const char* sample_word) {
  SdfSamples s;
  s.dim = dim;
  s.points.resize(n, dim);
  s.values.resize(n);
  for (std::int64_t i = 0; i < n; ++i) {
    for (int a = 0; a < dim; ++a) {
      const double x = P.data[i * pstride + a];
      if (!std::isfinite(x))
        throw InputError(ppath, 0,
                         std::string(sample_word) + " " + std::to_string(i) +
                             " has a non-finite coordinate (" + FormatDouble(x) + ")");
      s.points(i, a) = x;
    }
    const double v = values[i * vstride];
    if (!std::isfinite(v))
      throw InputError(vpath, 0,
                       "value of sample " + std::to_string(i) + " is not finite (" +
                           FormatDouble(v) + ")");
    s.values[i] = v;
  }
  return s;
}

void CheckSamples(const std::string& path, const SdfSamples& s) {
  if (s.dim != 2 && s.dim != 3)
    throw Error("cannot write '" + path + "': SdfSamples::dim must be 2 or 3, got " +
                std::to_string(s.dim));
  if (s.points.rows() != s.values.size() || s.points.cols() != s.dim)
    throw Error("cannot write '" + path + "': points are " + std::to_string(s.points.rows()) +
                " x " + std::to_string(s.points.cols()) + " but there are " +
                std::to_string(s.values.size()) + " values of dimension " + std::to_string(s.dim));
}

}  // namespace

std::string SdfBoundsPath(const std::string& values_npy) { return values_npy + ".bounds"; }

SdfSamples ReadSdfGrid(const std::string& values_npy, const std::array<double, 3>& min,
                       const std::array<double, 3>& max) {
  return GridFromArray(values_npy, ReadNpy(values_npy), min, max);
}

void WriteSdfGrid(const std::string& values_npy, const SdfSamples& s) {
  if (!s.grid)
    throw Error("cannot write '" + values_npy + "' as a grid: the samples have no grid layout");
  const GridInfo& g = *s.grid;
  if ((g.dim != 2 && g.dim != 3) || g.dims[0] < 1 || g.dims[1] < 1 ||
      (g.dim == 3 && g.dims[2] < 1) || s.values.size() != g.NumNodes())
    throw Error("cannot write '" + values_npy + "': grid of " + std::to_string(g.NumNodes()) +
                " nodes but " + std::to_string(s.values.size()) + " values");
  const int nx = g.dims[0], ny = g.dims[1], nz = g.dim == 3 ? g.dims[2] : 1;
  std::vector<double> out(static_cast<std::size_t>(g.NumNodes()));
  for (int i = 0; i < nx; ++i) {
    for (int j = 0; j < ny; ++j) {
      for (int k = 0; k < nz; ++k) {
        out[(static_cast<std::size_t>(i) * ny + j) * nz + k] =
            s.values[i + static_cast<std::int64_t>(nx) * (j + static_cast<std::int64_t>(ny) * k)];
      }
    }
  }
  std::vector<std::int64_t> shape = {nx, ny};
  if (g.dim == 3) shape.push_back(nz);
  WriteNpy(values_npy, out.data(), shape);
  std::string b = g.dim == 3 ? "# arcs grid bounds: xmin ymin zmin xmax ymax zmax\n"
                             : "# arcs grid bounds: xmin ymin xmax ymax\n";
  for (const auto* v : {&g.min, &g.max}) {
    for (int a = 0; a < g.dim; ++a) {
      if (a) b += ' ';
      AppendDouble(&b, (*v)[a]);
    }
    b += v == &g.min ? ' ' : '\n';
  }
  WriteWholeFile(SdfBoundsPath(values_npy), b);
}

SdfSamples ReadSdfScattered(const std::string& points_npy, const std::string& values_npy) {
  const NpyArray P = ReadNpy(points_npy);
  const NpyArray V = ReadNpy(values_npy);
  if (P.Ndim() != 2 || (P.shape[1] != 2 && P.shape[1] != 3))
    throw InputError(points_npy, 0,
                     "points must have shape (N, 3) or (N, 2), got " + NpyShapeString(P.shape));
  if (!(V.Ndim() == 1 || (V.Ndim() == 2 && V.shape[1] == 1)))
    throw InputError(values_npy, 0,
                     "values must have shape (N,) or (N, 1), got " + NpyShapeString(V.shape));
  if (P.shape[0] != V.shape[0])
    throw InputError(values_npy, 0,
                     "has " + std::to_string(V.shape[0]) + " values but '" + points_npy +
                         "' has " + std::to_string(P.shape[0]) +
                         " points (both files must have the same length)");
  const int dim = static_cast<int>(P.shape[1]);
  return FromColumns(points_npy, P, dim, dim, values_npy, V.data.data(), 1, P.shape[0], "point");
}

SdfSamples ReadSdfText(const std::string& path) {
  const FileBytes file = ReadWholeFile(path);
  const std::string_view text = file.view();
  CheckIsText(path, text, "SDF text");
  LineReader lines(text);
  std::string_view line, tok;
  int cols = 0;
  std::vector<double> vals;
  while (lines.Next(&line)) {
    Tokenizer tk(StripComment(line));
    const int n = tk.CountRemaining();
    if (n == 0) continue;
    const long ln = lines.line();
    if (cols == 0) {
      if (n != 3 && n != 4)
        ThrowAtLine(path, ln,
                    "expected 'x y z s' (4 columns) or 'x y s' (3 columns), found " +
                        std::to_string(n) + " columns");
      cols = n;
    } else if (n != cols) {
      ThrowAtLine(path, ln,
                  "found " + std::to_string(n) + " columns, but the first sample line has " +
                      std::to_string(cols));
    }
    while (tk.Next(&tok)) {
      double v = 0;
      const NumStatus st = ParseDouble(tok, &v);
      if (st != NumStatus::kOk) ThrowAtLine(path, ln, "bad number " + Quote(tok));
      if (!std::isfinite(v)) ThrowAtLine(path, ln, "non-finite value " + Quote(tok));
      vals.push_back(v);
    }
  }
  if (cols == 0) ThrowAtLine(path, 0, "no samples found");
  const int dim = cols - 1;
  const std::int64_t n = static_cast<std::int64_t>(vals.size()) / cols;
  SdfSamples s;
  s.dim = dim;
  s.points.resize(n, dim);
  s.values.resize(n);
  for (std::int64_t i = 0; i < n; ++i) {
    for (int a = 0; a < dim; ++a) s.points(i, a) = vals[i * cols + a];
    s.values[i] = vals[i * cols + dim];
  }
  return s;
}

void WriteSdfText(const std::string& path, const SdfSamples& s) {
  CheckSamples(path, s);
  std::string out = s.dim == 3 ? "# arcs SDF samples: x y z s\n" : "# arcs SDF samples: x y s\n";
  out.reserve(out.size() + static_cast<std::size_t>(s.values.size()) * 24 * (s.dim + 1));
  for (std::int64_t i = 0; i < s.values.size(); ++i) {
    for (int a = 0; a < s.dim; ++a) {
      AppendDouble(&out, s.points(i, a));
      out += ' ';
    }
    AppendDouble(&out, s.values[i]);
    out += '\n';
  }
  WriteWholeFile(path, out);
}

namespace {

SdfSamples ReadSdfNpz(const std::string& path) {
  const auto members = ReadNpz(path);
  const NpyArray *U = nullptr, *S = nullptr, *B = nullptr;
  std::string names;
  for (const auto& [k, a] : members) {
    names += (names.empty() ? "" : ", ") + k;
    if (k == "U") U = &a;
    if (k == "S") S = &a;
    if (k == "bounds") B = &a;
  }
  if (!S) throw InputError(path, 0, "an SDF .npz needs an array 'S' (and 'U' for scattered samples); it has: " + names);
  if (S->Ndim() == 2 && S->shape[1] == 1 && U) {
    // (N, 1) values: scattered.
  } else if (S->Ndim() == 2 || S->Ndim() == 3) {
    const int dim = S->Ndim();
    std::array<double, 3> lo{-1, -1, -1}, hi{1, 1, 1};
    std::string origin = "the default bounds";
    if (B) {
      if (B->Ndim() != 2 || B->shape[0] != 2 || B->shape[1] != dim)
        throw InputError(path, 0, "'bounds' must have shape (2, " + std::to_string(dim) + ") ([min, max]) for a grid 'S' of shape " +
                                      NpyShapeString(S->shape) + ", got " + NpyShapeString(B->shape));
      for (int a = 0; a < dim; ++a) {
        lo[a] = B->data[a];
        hi[a] = B->data[dim + a];
      }
      origin = "'bounds'";
    }
    return SdfGridFromArray(path + ": 'S'", *S, lo, hi, origin);
  }
  if (!(S->Ndim() == 1 || (S->Ndim() == 2 && S->shape[1] == 1)))
    throw InputError(path, 0, "'S' must have shape (N,) with 'U' (N, 3) or (N, 2), or be a grid (nx, ny[, nz]); got " +
                                  NpyShapeString(S->shape));
  if (!U) throw InputError(path, 0, "'S' of shape " + NpyShapeString(S->shape) + " holds scattered values: 'U' (the points) is missing");
  if (U->Ndim() != 2 || (U->shape[1] != 2 && U->shape[1] != 3))
    throw InputError(path, 0, "'U' must have shape (N, 3) or (N, 2), got " + NpyShapeString(U->shape));
  if (U->shape[0] != S->shape[0])
    throw InputError(path, 0, "'U' has " + std::to_string(U->shape[0]) + " points but 'S' has " +
                                  std::to_string(S->shape[0]) + " values (they must have the same length)");
  const int dim = static_cast<int>(U->shape[1]);
  return FromColumns(path + ": 'U'", *U, dim, dim, path + ": 'S'", S->data.data(), 1, U->shape[0], "point");
}

// The grid's nodes in numpy C order (meshgrid indexing='ij'), one row each.
std::vector<double> GridNodesCOrder(const SdfSamples& s) {
  const GridInfo& g = *s.grid;
  const int nx = g.dims[0], ny = g.dims[1], nz = g.dim == 3 ? g.dims[2] : 1;
  std::vector<double> out;
  out.reserve(static_cast<std::size_t>(g.NumNodes()) * g.dim);
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j)
      for (int k = 0; k < nz; ++k) {
        const std::int64_t a = i + static_cast<std::int64_t>(nx) * (j + static_cast<std::int64_t>(ny) * k);
        for (int c = 0; c < g.dim; ++c) out.push_back(s.points(a, c));
      }
  return out;
}

std::vector<double> GridValuesCOrder(const SdfSamples& s) {
  const GridInfo& g = *s.grid;
  const int nx = g.dims[0], ny = g.dims[1], nz = g.dim == 3 ? g.dims[2] : 1;
  std::vector<double> out(static_cast<std::size_t>(g.NumNodes()));
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j)
      for (int k = 0; k < nz; ++k)
        out[(static_cast<std::size_t>(i) * ny + j) * nz + k] =
            s.values[i + static_cast<std::int64_t>(nx) * (j + static_cast<std::int64_t>(ny) * k)];
  return out;
}

}  // namespace

void WriteSdfNpz(const std::string& path, const SdfSamples& s) {
  CheckSamples(path, s);
  std::vector<NpzMember> m(2);
  m[0].name = "U";
  m[1].name = "S";
  const std::int64_t n = s.values.size();
  if (s.grid) {
    const GridInfo& g = *s.grid;
    m[0].data = GridNodesCOrder(s);
    m[0].shape = {n, g.dim};
    m[1].data = GridValuesCOrder(s);
    m[1].shape = {g.dims[0], g.dims[1]};
    if (g.dim == 3) m[1].shape.push_back(g.dims[2]);
    NpzMember b;
    b.name = "bounds";
    b.shape = {2, g.dim};
    for (const auto* v : {&g.min, &g.max})
      for (int a = 0; a < g.dim; ++a) b.data.push_back((*v)[a]);
    m.push_back(std::move(b));
  } else {
    m[0].shape = {n, s.dim};
    m[0].data.assign(s.points.data(), s.points.data() + n * s.dim);  // row-major = C order
    m[1].shape = {n};
    m[1].data.assign(s.values.data(), s.values.data() + n);
  }
  WriteNpz(path, m);
}

void WriteSdf(const std::string& path, const SdfSamples& s) {
  const std::string ext = LowerExtension(path);
  if (ext == ".txt" || ext == ".xyzs" || ext == ".sdf") return WriteSdfText(path, s);
  if (ext == ".npz") return WriteSdfNpz(path, s);
  if (ext != ".npy")
    throw InputError(path, 0, "unsupported SDF output extension '" + ext +
                                  "' (supported: .npy (grid, or (N, d+1) rows 'x y z s'), .npz (U, S, bounds), "
                                  ".txt .xyzs .sdf (text 'x y z s'))");
  if (s.grid) return WriteSdfGrid(path, s);
  CheckSamples(path, s);
  const std::int64_t n = s.values.size();
  std::vector<double> rows(static_cast<std::size_t>(n) * (s.dim + 1));
  for (std::int64_t i = 0; i < n; ++i) {
    for (int a = 0; a < s.dim; ++a) rows[i * (s.dim + 1) + a] = s.points(i, a);
    rows[i * (s.dim + 1) + s.dim] = s.values[i];
  }
  WriteNpy(path, rows.data(), {n, s.dim + 1});
  // A stale bounds sidecar would make ReadSdf read these rows as a 2D grid.
  std::error_code ec;
  std::filesystem::remove(SdfBoundsPath(path), ec);
}

SdfSamples ReadSdf(const std::string& path) {
  const std::string ext = LowerExtension(path);
  if (ext == ".txt" || ext == ".xyzs" || ext == ".sdf") return ReadSdfText(path);
  if (ext == ".npz") return ReadSdfNpz(path);
  if (ext != ".npy")
    throw InputError(path, 0,
                     "unsupported SDF file extension '" + ext +
                         "' (supported: .npy, .npz, .txt, .xyzs, .sdf)");
  const NpyArray arr = ReadNpy(path);
  const bool sidecar = FileExists(SdfBoundsPath(path));
  if (arr.Ndim() == 3) return GridFromArray(path, arr, {-1, -1, -1}, {1, 1, 1});
  if (arr.Ndim() == 2) {
    const std::int64_t c = arr.shape[1];
    if (!sidecar && (c == 3 || c == 4)) {
      const int dim = static_cast<int>(c - 1);
      return FromColumns(path, arr, dim, c, path, arr.data.data() + dim, c, arr.shape[0],
                         "sample");
    }
    return GridFromArray(path, arr, {-1, -1, -1}, {1, 1, 1});
  }
  throw InputError(path, 0,
                   "cannot tell the SDF layout of an array of shape " + NpyShapeString(arr.shape) +
                       ": expected (nx, ny, nz) for a 3D grid, (N, 4) for 3D samples 'x y z s', "
                       "(N, 3) for 2D samples 'x y s', or (nx, ny) for a 2D grid");
}

}  // namespace arcs
