#include "framework/geometry/curves.h"

#include "framework/error.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <numbers>
#include <sstream>

namespace arcs {

namespace {

constexpr double kPi = std::numbers::pi;

using Pts = std::vector<Eigen::Vector2d>;

// Resamples a closed dense polygon to k points at equal arc-length steps,
// starting at the first point.
Pts ResampleClosed(const Pts& dense, int k) {
  const int m = static_cast<int>(dense.size());
  std::vector<double> cum(m + 1, 0.0);
  for (int i = 0; i < m; ++i) cum[i + 1] = cum[i] + (dense[(i + 1) % m] - dense[i]).norm();
  const double total = cum[m];
  Pts out;
  out.reserve(k);
  int seg = 0;
  for (int j = 0; j < k; ++j) {
    const double s = total * j / k;
    while (seg < m - 1 && cum[seg + 1] <= s) ++seg;
    const double len = cum[seg + 1] - cum[seg];
    const double t = len > 0 ? (s - cum[seg]) / len : 0.0;
    out.push_back((1 - t) * dense[seg] + t * dense[(seg + 1) % m]);
  }
  return out;
}

// A closed parametric curve f(t), t in [0, 1), densely sampled then resampled
// uniformly by arc length.
Pts Parametric(const std::function<Eigen::Vector2d(double)>& f, int k) {
  const int dense = std::max(16 * k, 4096);
  Pts d(dense);
  for (int i = 0; i < dense; ++i) d[i] = f(static_cast<double>(i) / dense);
  return ResampleClosed(d, k);
}

Eigen::Vector2d Polar(double r, double a) { return {r * std::cos(a), r * std::sin(a)}; }

double WrapAngle(double a) { return std::remainder(a, 2 * kPi); }

// Appends a closed chain of points (counter-clockwise for outer boundaries).
void AddLoop(Polyline* c, const Pts& pts, bool reverse = false) {
  const int base = c->NumVertices();
  const int k = static_cast<int>(pts.size());
  c->V.conservativeResize(base + k, 3);
  c->E.conservativeResize(c->NumEdges() + k, 2);
  const int e0 = c->NumEdges() - k;
  for (int i = 0; i < k; ++i) {
    const Eigen::Vector2d& p = pts[reverse ? k - 1 - i : i];
    c->V.row(base + i) << p.x(), p.y(), 0.0;
    c->E.row(e0 + i) << base + i, base + (i + 1) % k;
  }
}

Pts Circle(Eigen::Vector2d c, double r, int k) {
  return Parametric([&](double t) -> Eigen::Vector2d { return c + Polar(r, 2 * kPi * t); }, k);
}

Pts LetterC(int k) {
  const double rm = 0.35, th = 0.12, a0 = kPi / 6, a1 = 2 * kPi - kPi / 6;
  Pts d;
  const int m = 4096;
  for (int i = 0; i < m; ++i) d.push_back(Polar(rm + th, a0 + (a1 - a0) * i / m));  // outer arc
  for (int i = 0; i < m / 4; ++i) d.push_back(Polar(rm, a1) + Polar(th, a1 + kPi * i / (m / 4)));  // end cap
  for (int i = 0; i < m; ++i) d.push_back(Polar(rm - th, a1 - (a1 - a0) * i / m));  // inner arc, back
  for (int i = 0; i < m / 4; ++i) d.push_back(Polar(rm, a0) + Polar(th, a0 + kPi + kPi * i / (m / 4)));  // start cap
  return ResampleClosed(d, k);
}

Pts Square(int k) {
  const int per = std::max(1, k / 4);
  const double h = 0.4;
  const Eigen::Vector2d c[4] = {{-h, -h}, {h, -h}, {h, h}, {-h, h}};
  Pts p;
  for (int s = 0; s < 4; ++s)
    for (int i = 0; i < per; ++i) p.push_back(c[s] + (c[(s + 1) % 4] - c[s]) * (static_cast<double>(i) / per));
  return p;
}

}  // namespace

std::vector<std::string> BuiltinCurveNames() {
  return {"circle", "ellipse", "star", "bunny", "letter_c", "square", "two_circles", "annulus"};
}

Polyline MakeBuiltinCurve(const std::string& name, int segments) {
  if (segments < 16) throw OptionError("MakeBuiltinCurve: segments = " + std::to_string(segments) + ": must be >= 16");
  Polyline c;
  c.V.resize(0, 3);
  c.E.resize(0, 2);
  const int k = segments;
  if (name == "circle") {
    AddLoop(&c, Circle({0, 0}, 0.5, k));
  } else if (name == "ellipse") {
    AddLoop(&c, Parametric([](double t) -> Eigen::Vector2d {
              return {0.5 * std::cos(2 * kPi * t), 0.3 * std::sin(2 * kPi * t)};
            }, k));
  } else if (name == "star") {
    AddLoop(&c, Parametric([](double t) {
              const double a = 2 * kPi * t;
              return Polar(0.32 * (1 + 0.55 * std::cos(5 * a)), a);
            }, k));
  } else if (name == "bunny") {
    // A round head (r = 0.25) with two long ears (Gaussian bumps in the polar
    // radius at 68 and 102 degrees): star-shaped but far from convex.
    AddLoop(&c, Parametric([](double t) {
              const double a = 2 * kPi * t;
              auto bump = [&](double centre, double width) {
                const double x = WrapAngle(a - centre) / width;
                return std::exp(-x * x);
              };
              const double r = 0.25 + 0.27 * bump(68 * kPi / 180, 0.13) + 0.25 * bump(102 * kPi / 180, 0.13) +
                               0.05 * bump(-90 * kPi / 180, 0.5);
              return Polar(r, a);
            }, k));
  } else if (name == "letter_c") {
    AddLoop(&c, LetterC(k));
  } else if (name == "square") {
    AddLoop(&c, Square(k));
  } else if (name == "two_circles") {
    const double r1 = 0.25, r2 = 0.17;
    const int k1 = std::max(8, static_cast<int>(std::lround(k * r1 / (r1 + r2))));
    AddLoop(&c, Circle({-0.22, 0.0}, r1, k1));
    AddLoop(&c, Circle({0.3, 0.05}, r2, std::max(8, k - k1)));
  } else if (name == "annulus") {
    const int k1 = std::max(8, static_cast<int>(std::lround(k * 2.0 / 3.0)));
    AddLoop(&c, Circle({0, 0}, 0.5, k1));
    AddLoop(&c, Circle({0, 0}, 0.25, std::max(8, k - k1)), /*reverse=*/true);  // a hole: clockwise
  } else {
    std::string names;
    for (const auto& n : BuiltinCurveNames()) {
      if (!names.empty()) names += ", ";
      names += n;
    }
    throw Error("unknown built-in curve '" + name + "' (built-in curves: " + names + ")");
  }
  return c;
}

Polyline MakeClosedPolyline(const MatrixXd& points) {
  if (points.cols() < 2) throw Error("MakeClosedPolyline: points need 2 or 3 columns");
  Pts p(points.rows());
  for (Eigen::Index i = 0; i < points.rows(); ++i) p[i] = {points(i, 0), points(i, 1)};
  Polyline c;
  c.V.resize(0, 3);
  c.E.resize(0, 2);
  if (!p.empty()) AddLoop(&c, p);
  return c;
}

void NormalizeCurve(Polyline* curve, double longest_side, bool center) {
  if (!(longest_side > 0)) throw OptionError("NormalizeCurve: longest_side must be > 0");
  if (curve->NumVertices() == 0) return;
  const Eigen::RowVector3d lo = curve->V.colwise().minCoeff(), hi = curve->V.colwise().maxCoeff();
  const double extent = (hi - lo).maxCoeff();
  Eigen::RowVector3d mid = 0.5 * (lo + hi);
  mid.z() = 0;
  if (center) curve->V.rowwise() -= mid;
  if (extent > 0) {
    const double s = longest_side / extent;
    if (center) {
      curve->V *= s;
    } else {  // scale about the bounding-box centre, keeping it in place
      curve->V.rowwise() -= mid;
      curve->V *= s;
      curve->V.rowwise() += mid;
    }
  }
}

void CheckPolyline(const Polyline& curve, const std::string& who) {
  if (curve.NumEdges() == 0) throw InputError(who, 0, "the curve has no edges");
  for (int v = 0; v < curve.NumVertices(); ++v) {
    if (!curve.V.row(v).allFinite())
      throw InputError(who, 0, "vertex " + std::to_string(v) + " has a non-finite coordinate");
    if (curve.V(v, 2) != 0.0)
      throw InputError(who, 0, "vertex " + std::to_string(v) + " has z = " + std::to_string(curve.V(v, 2)) +
                                   " (a 2D curve lies in z = 0)");
  }
  for (int e = 0; e < curve.NumEdges(); ++e)
    for (int k = 0; k < 2; ++k)
      if (curve.E(e, k) < 0 || curve.E(e, k) >= curve.NumVertices())
        throw InputError(who, 0, "edge " + std::to_string(e) + " refers to vertex " + std::to_string(curve.E(e, k)) +
                                     " of " + std::to_string(curve.NumVertices()));
}

double PolylineLength(const Polyline& curve) {
  double l = 0;
  for (int e = 0; e < curve.NumEdges(); ++e) l += (curve.V.row(curve.E(e, 1)) - curve.V.row(curve.E(e, 0))).norm();
  return l;
}

double PolylineSignedArea(const Polyline& curve) {
  double a = 0;
  for (int e = 0; e < curve.NumEdges(); ++e) {
    const auto p = curve.V.row(curve.E(e, 0)), q = curve.V.row(curve.E(e, 1));
    a += p.x() * q.y() - q.x() * p.y();
  }
  return 0.5 * a;
}

CurveTopology ComputeCurveTopology(const Polyline& curve) {
  const int nv = curve.NumVertices(), ne = curve.NumEdges();
  std::vector<int> in(nv, 0), out(nv, 0), parent(nv);
  for (int v = 0; v < nv; ++v) parent[v] = v;
  std::function<int(int)> find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (int e = 0; e < ne; ++e) {
    const int a = curve.E(e, 0), b = curve.E(e, 1);
    ++out[a];
    ++in[b];
    parent[find(a)] = find(b);
  }
  CurveTopology t;
  std::vector<int> comp_id(nv, -1);
  std::vector<char> comp_closed;
  std::vector<double> comp_area;
  for (int v = 0; v < nv; ++v) {
    if (in[v] + out[v] == 0) continue;
    const int r = find(v);
    if (comp_id[r] < 0) {
      comp_id[r] = t.components++;
      comp_closed.push_back(1);
      comp_area.push_back(0.0);
    }
    const int c = comp_id[r];
    const int deg = in[v] + out[v];
    if (deg == 1) ++t.open_ends;
    if (deg > 2 || (deg == 2 && in[v] != 1)) ++t.branch_vertices;
    if (in[v] != 1 || out[v] != 1) comp_closed[c] = 0;
  }
  for (int e = 0; e < ne; ++e) {
    const auto p = curve.V.row(curve.E(e, 0)), q = curve.V.row(curve.E(e, 1));
    comp_area[comp_id[find(curve.E(e, 0))]] += 0.5 * (p.x() * q.y() - q.x() * p.y());
  }
  for (int c = 0; c < t.components; ++c) {
    t.closed_components += comp_closed[c];
    if (comp_closed[c] && comp_area[c] < 0) ++t.holes;
  }
  return t;
}

// ---- files -------------------------------------------------------------------

namespace {

std::string Lower(std::string s) {
  for (char& ch : s) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return s;
}

std::string Extension(const std::string& path) {
  const auto slash = path.find_last_of('/');
  const auto dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  return Lower(path.substr(dot));
}

double ParseDouble(const std::string& tok, const std::string& path, long line, const char* what) {
  double v = 0;
  const char* b = tok.data();
  const char* e = b + tok.size();
  if (!tok.empty() && *b == '+') ++b;
  const auto r = std::from_chars(b, e, v);
  if (r.ec != std::errc() || r.ptr != e)
    throw InputError(path, line, std::string("bad ") + what + " '" + tok.substr(0, 40) + "'");
  if (!std::isfinite(v)) throw InputError(path, line, std::string(what) + " is not finite ('" + tok + "')");
  return v;
}

// Chains of the edge graph: maximal paths following each vertex's single
// successor; closed chains repeat their first vertex at the end.
std::vector<std::vector<int>> Chains(const Polyline& c) {
  const int nv = c.NumVertices(), ne = c.NumEdges();
  std::vector<int> out_count(nv, 0), in_count(nv, 0), first_out(nv, -1);
  std::vector<int> next_edge(ne, -1);  // further out-edges of the same vertex, in order
  std::vector<int> last_out(nv, -1);
  for (int e = 0; e < ne; ++e) {
    const int a = c.E(e, 0);
    ++out_count[a];
    ++in_count[c.E(e, 1)];
    if (first_out[a] < 0) first_out[a] = e;
    else next_edge[last_out[a]] = e;
    last_out[a] = e;
  }
  std::vector<char> used(ne, 0);
  std::vector<std::vector<int>> chains;
  auto take_out = [&](int v) {
    for (int e = first_out[v]; e >= 0; e = next_edge[e])
      if (!used[e]) return e;
    return -1;
  };
  auto walk = [&](int e) {
    std::vector<int> ch{c.E(e, 0)};
    while (e >= 0) {
      used[e] = 1;
      const int b = c.E(e, 1);
      ch.push_back(b);
      if (in_count[b] != 1 || out_count[b] != 1) break;  // stop at ends and branch points
      e = take_out(b);
    }
    chains.push_back(std::move(ch));
  };
  // Open chains start where a path cannot be continued backwards.
  for (int e = 0; e < ne; ++e) {
    const int a = c.E(e, 0);
    if (!used[e] && (in_count[a] != 1 || out_count[a] != 1)) walk(e);
  }
  for (int e = 0; e < ne; ++e)
    if (!used[e]) walk(e);
  return chains;
}

std::string Num(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

}  // namespace

Polyline ReadPolyline(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, "cannot open the curve file");
  Polyline c;
  std::vector<Eigen::Vector2d> verts;
  std::vector<std::array<int, 2>> edges;
  std::vector<long> edge_line;
  std::string line;
  long ln = 0;
  while (std::getline(in, line)) {
    ++ln;
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    std::istringstream ss(line);
    std::string key;
    if (!(ss >> key)) continue;
    std::vector<std::string> tok;
    for (std::string t; ss >> t;) tok.push_back(t);
    if (key == "v") {
      if (tok.size() < 2 || tok.size() > 3)
        throw InputError(path, ln, "a vertex needs 2 or 3 coordinates ('v x y [0]'), got " + std::to_string(tok.size()));
      const double x = ParseDouble(tok[0], path, ln, "x coordinate");
      const double y = ParseDouble(tok[1], path, ln, "y coordinate");
      if (tok.size() == 3 && ParseDouble(tok[2], path, ln, "z coordinate") != 0.0)
        throw InputError(path, ln, "z = " + tok[2] + ": a 2D curve lies in z = 0");
      verts.emplace_back(x, y);
    } else if (key == "l") {
      if (tok.size() < 2) throw InputError(path, ln, "a line element needs at least 2 vertex indices");
      std::vector<int> ids;
      for (const auto& t : tok) {
        const std::string idx = t.substr(0, t.find('/'));  // OBJ "i/vt" form
        long v = 0;
        const auto r = std::from_chars(idx.data(), idx.data() + idx.size(), v);
        if (r.ec != std::errc() || r.ptr != idx.data() + idx.size() || v == 0)
          throw InputError(path, ln, "bad vertex index '" + t.substr(0, 40) + "' (1-based, or negative = relative)");
        const long n = static_cast<long>(verts.size());
        const long zero_based = v > 0 ? v - 1 : n + v;
        if (zero_based < 0 || zero_based >= n)
          throw InputError(path, ln, "vertex index " + t + " out of range (" + std::to_string(n) + " vertices so far)");
        ids.push_back(static_cast<int>(zero_based));
      }
      for (size_t i = 0; i + 1 < ids.size(); ++i) {
        if (ids[i] == ids[i + 1]) throw InputError(path, ln, "an edge from vertex " + std::to_string(ids[i] + 1) + " to itself");
        edges.push_back({ids[i], ids[i + 1]});
        edge_line.push_back(ln);
      }
    } else if (key == "f") {
      throw InputError(path, ln, "faces ('f') in a curve file: expected 'v' and 'l' lines only (a 2D polyline)");
    } else if (key == "o" || key == "g" || key == "s" || key == "usemtl" || key == "mtllib" || key == "vt" ||
               key == "vn") {
      continue;
    } else {
      throw InputError(path, ln, "unknown element '" + key.substr(0, 40) + "' (expected 'v x y' or 'l i j ...')");
    }
  }
  if (edges.empty()) throw InputError(path, 0, "no edges ('l' lines) in the curve file");
  c.V.resize(static_cast<Eigen::Index>(verts.size()), 3);
  for (size_t i = 0; i < verts.size(); ++i) c.V.row(static_cast<Eigen::Index>(i)) << verts[i].x(), verts[i].y(), 0.0;
  c.E.resize(static_cast<Eigen::Index>(edges.size()), 2);
  for (size_t i = 0; i < edges.size(); ++i) c.E.row(static_cast<Eigen::Index>(i)) << edges[i][0], edges[i][1];
  return c;
}

void WritePolyline(const std::string& path, const Polyline& curve) {
  const std::string ext = Extension(path);
  std::string s;
  if (ext == ".obj" || ext == ".txt" || ext == ".poly") {
    s = "# arcs 2D polyline: 'v x y 0' vertices, 'l i j ...' 1-based chains (closed chains repeat the first)\n";
    for (int v = 0; v < curve.NumVertices(); ++v)
      s.append("v ").append(Num(curve.V(v, 0))).append(" ").append(Num(curve.V(v, 1))).append(" 0\n");
    for (const auto& ch : Chains(curve)) {
      s += "l";
      for (int v : ch) s.append(" ").append(std::to_string(v + 1));
      s += "\n";
    }
  } else if (ext == ".svg") {
    double x0 = 0, y0 = 0, x1 = 1, y1 = 1;
    if (curve.NumVertices() > 0) {
      x0 = curve.V.col(0).minCoeff(), x1 = curve.V.col(0).maxCoeff();
      y0 = curve.V.col(1).minCoeff(), y1 = curve.V.col(1).maxCoeff();
    }
    const double pad = 0.05 * std::max({x1 - x0, y1 - y0, 1e-9});
    x0 -= pad, y0 -= pad, x1 += pad, y1 += pad;
    const double w = x1 - x0, h = y1 - y0, px = 800.0 / std::max(w, h);
    s = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + Num(w * px) + "\" height=\"" + Num(h * px) +
        "\" viewBox=\"" + Num(x0) + " " + Num(-y1) + " " + Num(w) + " " + Num(h) + "\">\n";
    // Flip y so that y points up; one path per chain, even-odd fill shows holes.
    s += "<path fill=\"#cfe3f7\" fill-rule=\"evenodd\" stroke=\"#1f4e8c\" stroke-width=\"" + Num(2.0 / px) +
         "\" d=\"";
    for (const auto& ch : Chains(curve)) {
      for (size_t i = 0; i < ch.size(); ++i)
        s.append(i == 0 ? "M" : "L").append(Num(curve.V(ch[i], 0))).append(" ").append(Num(-curve.V(ch[i], 1))).append(" ");
      if (ch.size() > 2 && ch.front() == ch.back()) s += "Z ";
    }
    s += "\"/>\n</svg>\n";
  } else {
    throw Error("WritePolyline: " + path + ": unknown extension '" + ext + "' (use .obj, .txt, .poly or .svg)");
  }
  std::ofstream out(path, std::ios::binary);
  if (!out) throw Error("cannot write the curve file " + path);
  out << s;
  if (!out) throw Error("error while writing the curve file " + path);
}

Polyline ToPolyline(const Polyline2& p) {
  Polyline c;
  c.V.resize(p.V.rows(), 3);
  for (Eigen::Index i = 0; i < p.V.rows(); ++i) c.V.row(i) << p.V(i, 0), p.V(i, 1), 0.0;
  c.E.resize(p.E.rows(), 2);
  for (Eigen::Index i = 0; i < p.E.rows(); ++i) c.E.row(i) << p.E(i, 0), p.E(i, 1);
  return c;
}

}  // namespace arcs
