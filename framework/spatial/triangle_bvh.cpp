// Closest point on a triangle mesh.
//
// Structure: a binary binned-SAH tree is built first and collapsed into a
// 4-wide tree whose nodes store, for each of their four children, an
// axis-aligned box and an oriented box in float, structure-of-arrays, so that
// the four lower bounds of a node are computed together (the loops vectorise
// with plain SSE2). Leaves hold up to 4 triangles, tested exactly in double.
//
// Why oriented boxes: most nodes of the RFTA grid are far from the surface. A
// far query must open every node whose lower bound is below its distance;
// with axis-aligned boxes that is a wide cap of the surface (the box of a
// tilted patch sticks out by its size), with oriented boxes fitted to the
// patch (normal + in-plane principal direction) only the patches that are
// really close. Measured on bunny (1M grid nodes): 275 -> 135 bound tests
// and 96 -> 23 triangle tests per query.
//
// Exactness and determinism: the float bounds are made conservative (boxes
// rounded outward, an absolute allowance for the rounding of the query and of
// the rotation, a relative one for the non-orthonormality of float frames),
// so they are true lower bounds. A query returns the lexicographic minimum of
// (squared distance, face index) over all faces: nodes are kept whenever their
// bound is within a relative 1e-12 of the current best, so the answer does not
// depend on the traversal order nor on the initial search radius (the batch
// API warm-starts each query from its neighbour in the same chunk, and chunks
// depend on the thread count).
#include "framework/spatial/triangle_bvh.h"

#include "framework/error.h"
#include "framework/spatial/knn.h"
#include "framework/spatial/topology.h"
#include "framework/util/parallel.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace arcs {
namespace {

// Triangles stored in leaf order: corners a, b, c (exact copies of the mesh
// vertices, so vertex-region answers are exact vertices).
struct Tri {
  double a[3], b[3], c[3];
};

// Binary build node (double box). Leaf: first triangle and count > 0. Inner:
// count == 0, left child is the next node (depth-first layout), right child
// index in `first`.
struct Node {
  double lo[3], hi[3];
  std::int32_t first = 0;
  std::int32_t count = 0;
};

// 4-wide query node, structure-of-arrays over the children: the last index of
// each array is the child (SIMD lane). Empty slots have empty boxes, lo = +inf
// > hi = -inf, so their bound is +inf. Coordinates are relative to the tree's
// origin (see Impl).
// The axis-aligned boxes and the children come first: a tree without oriented
// boxes reads only those (two cache lines of the node's six).
struct alignas(64) Node4 {
  float lo[3][4], hi[3][4];    // axis-aligned boxes, rounded outward
  std::int32_t child[4];     // inner: node index; leaf: first triangle
  std::int32_t count[4];     // 0: inner node; > 0: leaf with count triangles; -1: empty
  float rot[9][4];             // oriented frames: rot[3 * k + c] = coordinate c of axis k
  float olo[3][4], ohi[3][4];  // extents along the oriented axes, rounded outward
};

// Relative slack of the pruning test. The bounds are true lower bounds; the
// slack only makes sure that exact ties are always examined.
constexpr double kPruneSlack = 1.0 + 1e-12;

inline double Dot3(const double* u, const double* v) { return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]; }

// Lower bounds of the squared distance from q to the triangles of each child:
// the larger of the axis-aligned and the oriented box distances, each gap
// reduced by `margin` (the float rounding of q and of rot * q), the result by
// a relative 4e-6 (float frames are orthonormal to ~1e-7). Without oriented
// boxes (Oriented false) the axis-aligned distance alone: the identity frame
// would give the same value, 1 * q + 0 + 0 = q exactly in float.
template <bool Oriented>
inline void ChildLowerBounds(const Node4& n, const float* q, float margin, float* out) {
#if defined(__SSE2__)
  // Baseline x86-64 SIMD: one lane per child.
  const __m128 zero = _mm_setzero_ps(), m = _mm_set1_ps(margin);
  const __m128 qv[3] = {_mm_set1_ps(q[0]), _mm_set1_ps(q[1]), _mm_set1_ps(q[2])};
  __m128 s = zero, o = zero;
  for (int k = 0; k < 3; ++k) {
    const __m128 gap = _mm_max_ps(_mm_sub_ps(_mm_load_ps(n.lo[k]), qv[k]),
                                  _mm_sub_ps(qv[k], _mm_load_ps(n.hi[k])));
    const __m128 d = _mm_max_ps(_mm_sub_ps(gap, m), zero);
    s = _mm_add_ps(s, _mm_mul_ps(d, d));
  }
  if constexpr (!Oriented) {
    _mm_store_ps(out, _mm_mul_ps(s, _mm_set1_ps(1.0f - 4e-6f)));
    return;
  }
  for (int k = 0; k < 3; ++k) {
    const __m128 r = _mm_add_ps(
        _mm_add_ps(_mm_mul_ps(_mm_load_ps(n.rot[3 * k]), qv[0]), _mm_mul_ps(_mm_load_ps(n.rot[3 * k + 1]), qv[1])),
        _mm_mul_ps(_mm_load_ps(n.rot[3 * k + 2]), qv[2]));
    const __m128 gap = _mm_max_ps(_mm_sub_ps(_mm_load_ps(n.olo[k]), r), _mm_sub_ps(r, _mm_load_ps(n.ohi[k])));
    const __m128 d = _mm_max_ps(_mm_sub_ps(gap, m), zero);
    o = _mm_add_ps(o, _mm_mul_ps(d, d));
  }
  _mm_store_ps(out, _mm_mul_ps(_mm_max_ps(s, o), _mm_set1_ps(1.0f - 4e-6f)));
#else
  for (int j = 0; j < 4; ++j) {
    float s = 0.0f, o = 0.0f;
    for (int k = 0; k < 3; ++k) {
      const float d = std::max(std::max(n.lo[k][j] - q[k], q[k] - n.hi[k][j]) - margin, 0.0f);
      s += d * d;
    }
    if constexpr (!Oriented) {
      out[j] = s * (1.0f - 4e-6f);
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      const float r = n.rot[3 * k][j] * q[0] + n.rot[3 * k + 1][j] * q[1] + n.rot[3 * k + 2][j] * q[2];
      const float d = std::max(std::max(n.olo[k][j] - r, r - n.ohi[k][j]) - margin, 0.0f);
      o += d * d;
    }
    out[j] = std::max(s, o) * (1.0f - 4e-6f);
  }
#endif
}

inline float RoundDown(double x) {
  float f = static_cast<float>(x);
  if (static_cast<double>(f) > x) f = std::nextafter(f, -INFINITY);
  return f;
}
inline float RoundUp(double x) {
  float f = static_cast<float>(x);
  if (static_cast<double>(f) < x) f = std::nextafter(f, INFINITY);
  return f;
}

// Closest point on segment [p0, p1] to q; returns the squared distance.
inline double SegmentClosest(const double* p0, const double* p1, const double* q, double* out) {
  const double d[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
  const double w[3] = {q[0] - p0[0], q[1] - p0[1], q[2] - p0[2]};
  const double dd = Dot3(d, d);
  double t = 0.0;
  if (dd > 0.0) t = std::clamp(Dot3(w, d) / dd, 0.0, 1.0);
  if (t == 0.0) {
    out[0] = p0[0], out[1] = p0[1], out[2] = p0[2];
  } else if (t == 1.0) {
    out[0] = p1[0], out[1] = p1[1], out[2] = p1[2];
  } else {
    for (int k = 0; k < 3; ++k) out[k] = p0[k] + t * d[k];
  }
  const double e[3] = {q[0] - out[0], q[1] - out[1], q[2] - out[2]};
  return Dot3(e, e);
}

// Degenerate triangle (collinear or coincident corners): closest of its edges.
inline double DegenerateClosest(const Tri& t, const double* q, double* out) {
  double p[3];
  double best = SegmentClosest(t.a, t.b, q, out);
  double d = SegmentClosest(t.b, t.c, q, p);
  if (d < best) best = d, out[0] = p[0], out[1] = p[1], out[2] = p[2];
  d = SegmentClosest(t.c, t.a, q, p);
  if (d < best) best = d, out[0] = p[0], out[1] = p[1], out[2] = p[2];
  return best;
}

// Closest point on a non-degenerate triangle by Voronoi regions (Ericson,
// Real-Time Collision Detection, 5.1.5). Returns the squared distance.
inline double TriClosest(const Tri& t, const double* q, double* out) {
  const double ab[3] = {t.b[0] - t.a[0], t.b[1] - t.a[1], t.b[2] - t.a[2]};
  const double ac[3] = {t.c[0] - t.a[0], t.c[1] - t.a[1], t.c[2] - t.a[2]};
  const double ap[3] = {q[0] - t.a[0], q[1] - t.a[1], q[2] - t.a[2]};
  auto finish = [&](double x, double y, double z) {
    out[0] = x, out[1] = y, out[2] = z;
    const double e[3] = {q[0] - x, q[1] - y, q[2] - z};
    return Dot3(e, e);
  };
  const double d1 = Dot3(ab, ap), d2 = Dot3(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return finish(t.a[0], t.a[1], t.a[2]);
  const double bp[3] = {q[0] - t.b[0], q[1] - t.b[1], q[2] - t.b[2]};
  const double d3 = Dot3(ab, bp), d4 = Dot3(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return finish(t.b[0], t.b[1], t.b[2]);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double v = d1 / (d1 - d3);
    return finish(t.a[0] + v * ab[0], t.a[1] + v * ab[1], t.a[2] + v * ab[2]);
  }
  const double cp[3] = {q[0] - t.c[0], q[1] - t.c[1], q[2] - t.c[2]};
  const double d5 = Dot3(ab, cp), d6 = Dot3(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return finish(t.c[0], t.c[1], t.c[2]);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double w = d2 / (d2 - d6);
    return finish(t.a[0] + w * ac[0], t.a[1] + w * ac[1], t.a[2] + w * ac[2]);
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return finish(t.b[0] + w * (t.c[0] - t.b[0]), t.b[1] + w * (t.c[1] - t.b[1]),
                  t.b[2] + w * (t.c[2] - t.b[2]));
  }
  const double denom = va + vb + vc;
  if (!(denom > 0.0)) return DegenerateClosest(t, q, out);  // rounding on slivers
  const double v = vb / denom, w = vc / denom;
  return finish(t.a[0] + ab[0] * v + ac[0] * w, t.a[1] + ab[1] * v + ac[1] * w,
                t.a[2] + ab[2] * v + ac[2] * w);
}

}  // namespace

struct TriangleBvh::Impl {
  Mesh mesh;
  std::vector<Node4> nodes;
  std::vector<Tri> tris;            // leaf order
  std::vector<std::int32_t> face;   // leaf order -> mesh face index
  std::vector<std::uint8_t> degenerate;
  // Float bounds are stored relative to `origin` (the bounding-box centre), so
  // their precision follows the mesh's extent, not its position.
  double origin[3] = {0, 0, 0};
  double coord_scale = 0.0;         // max |coordinate - origin| over the mesh
  int max_depth = 0;                // of the 4-wide tree (sizes the traversal stack)
  bool oriented = true;             // false: the oriented boxes are the axis-aligned ones
  bool morton = false;              // the Morton-order split instead of the binned SAH

  void Build();
  // Oriented box of triangles [begin, end) into slot j of `node`.
  // Sums over a set of triangles (coordinates relative to `origin`): area
  // normals, corners, and corners' second moments (xx, yy, zz, xy, xz, yz).
  struct Moments {
    double n[3] = {0, 0, 0}, s[3] = {0, 0, 0}, m[6] = {0, 0, 0, 0, 0, 0};
    std::int64_t count = 0;  // triangles
    void Add(const Moments& o) {
      for (int k = 0; k < 3; ++k) n[k] += o.n[k], s[k] += o.s[k];
      for (int k = 0; k < 6; ++k) m[k] += o.m[k];
      count += o.count;
    }
  };
  Moments TriMoments(int t) const;
  // Each leaf's distinct triangle corners, relative to `origin`, in leaf
  // order (structure of arrays); the corners of triangles [t, e) for leaf
  // boundaries t, e are [start[t], start[e]). Only the
  // oriented fit reads them (a node's extents over its corners); a corner
  // shared by a leaf's triangles is projected once.
  struct Corners {
    std::vector<double> x, y, z;
    std::vector<std::int32_t> start;  // per triangle; set at leaf starts and at #triangles
  };
  void FitOrientedBox(const Moments& mo, const Corners& corners, int begin, int end, Node4* node, int j) const;
  // Lexicographic minimum of (sq_dist, face) over faces with sq_dist <=
  // max_sq; face -1 when none.
  // `tri` (optional) receives the internal (leaf-order) triangle index.
  TriangleBvh::Hit Query(const double* q, double max_sq, int* tri = nullptr) const;
  template <bool Oriented, class Entry>
  TriangleBvh::Hit QueryWith(const double* q, double max_sq, Entry* stack, int* tri) const;
  double TriSqDist(int i, const double* q, double* p) const {
    return degenerate[i] ? DegenerateClosest(tris[i], q, p) : TriClosest(tris[i], q, p);
  }
};

namespace {

struct BuildItem {
  double lo[3], hi[3], c[3];
  std::int32_t face;
};

struct Bounds {
  double lo[3] = {INFINITY, INFINITY, INFINITY};
  double hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  void Grow(const double* l, const double* h) {
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], l[k]), hi[k] = std::max(hi[k], h[k]);
  }
  void GrowPoint(const double* p) { Grow(p, p); }
  double HalfArea() const {
    const double d0 = hi[0] - lo[0], d1 = hi[1] - lo[1], d2 = hi[2] - lo[2];
    if (!(d0 >= 0.0)) return 0.0;
    return d0 * d1 + d1 * d2 + d2 * d0;
  }
};

constexpr int kBins = 16;
constexpr int kMaxLeaf = 4;

// Bin of centroid coordinate c in [lo, lo + extent]: always in [0, kBins),
// for any finite input. The position is a quotient (not c * (kBins / extent)):
// a subnormal extent makes kBins / extent infinite and 0 * inf NaN, and a NaN
// cast to int is undefined (it gave INT_MIN, an out-of-bounds index). An
// overflowing extent (+inf) gives t = 0; NaN goes to bin 0.
inline int BinOf(double c, double lo, double extent) {
  const double t = (c - lo) / extent * kBins;
  if (!(t > 0.0)) return 0;
  if (t >= kBins - 1) return kBins - 1;
  return static_cast<int>(t);
}

// BinOf with the quotient hoisted: (c - lo) * (kBins / extent) when that
// scale is finite (one multiply per item instead of a division), else the
// quotient itself. Bins may differ from BinOf's by one at a bin boundary
// (rounding); the build only needs the same bin for the same item every time.
struct Binner {
  double lo, extent, scale;
  bool finite;
  Binner(double lo_, double extent_) : lo(lo_), extent(extent_), scale(kBins / extent_) {
    finite = std::isfinite(scale) && scale > 0.0;
  }
  int operator()(double c) const {
    if (!finite) return BinOf(c, lo, extent);
    const double t = (c - lo) * scale;
    if (!(t > 0.0)) return 0;
    if (t >= kBins - 1) return kBins - 1;
    return static_cast<int>(t);
  }
};

}  // namespace

namespace {

// Spreads the low 21 bits of v to every third bit.
inline std::uint64_t Spread3(std::uint64_t v) {
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffULL;
  v = (v | v << 16) & 0x1f0000ff0000ffULL;
  v = (v | v << 8) & 0x100f00f00f00f00fULL;
  v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
  v = (v | v << 2) & 0x1249249249249249ULL;
  return v;
}

// The cheap build (meshes queried a few times per triangle, e.g. each
// fine-tuning iteration's surface): items sorted by the Morton code of their
// centroid (ties by face), each range split where its codes' highest
// differing bit changes (the middle when all codes are equal), down to leaves
// of at most kMaxLeaf; boxes bottom-up. O(F log F) in a sort, instead of the
// SAH build's binning passes at every level. The layout is the one the SAH
// build has after its re-layout (depth-first, left child = parent + 1,
// inner first = right child), and the answers
// are the same (exact, ties to the lowest face index), only the traversal
// differs.
void MortonTopology(std::vector<BuildItem>& items, std::vector<Node>& bin) {
  const int nf = static_cast<int>(items.size());
  Bounds cbox;
  for (const BuildItem& it : items) cbox.GrowPoint(it.c);
  std::vector<std::pair<std::uint64_t, std::int32_t>> code(nf);
  constexpr double kCells = 2097152.0;  // 2^21
  double scale[3];
  for (int k = 0; k < 3; ++k) {
    const double extent = cbox.hi[k] - cbox.lo[k];
    scale[k] = extent > 0.0 && std::isfinite(kCells / extent) ? kCells / extent : 0.0;
  }
  ParallelFor(nf, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t i = b; i < e; ++i) {
      std::uint64_t m = 0;
      for (int k = 0; k < 3; ++k) {
        const double t = (items[i].c[k] - cbox.lo[k]) * scale[k];
        const std::uint64_t q = !(t > 0.0) ? 0 : t >= kCells - 1 ? std::uint64_t(kCells - 1) : std::uint64_t(t);
        m |= Spread3(q) << k;
      }
      code[i] = {m, items[i].face};
    }
  }, 8192);
  // The (code, face) pairs are distinct: any sort gives the one order.
  tbb::parallel_sort(code.begin(), code.end());
  {
    std::vector<BuildItem> sorted(nf);
    // Face f is item f before sorting.
    ParallelFor(nf, [&](std::int64_t b, std::int64_t e) {
      for (std::int64_t i = b; i < e; ++i) sorted[i] = items[code[i].second];
    }, 8192);
    items.swap(sorted);
  }
  // Emitted depth-first (left child = parent + 1, `first` = the right
  // child, patched when the right child is emitted), the layout Build's
  // re-layout gives the SAH tree.
  struct Task {
    int parent, begin, end;  // parent: the node whose right child this is, or -1
  };
  bin.clear();
  bin.reserve(std::max(1, 2 * (nf / kMaxLeaf + 1)));
  std::vector<Task> stack{{-1, 0, nf}};
  while (!stack.empty()) {
    const Task t = stack.back();
    stack.pop_back();
    const int node = static_cast<int>(bin.size());
    bin.emplace_back();
    if (t.parent >= 0) bin[t.parent].first = node;
    const int n = t.end - t.begin;
    if (n <= kMaxLeaf) {
      bin[node].first = t.begin;
      bin[node].count = n;
      continue;
    }
    const std::uint64_t a = code[t.begin].first, b = code[t.end - 1].first;
    int mid = t.begin + n / 2;
    if (a != b) {
      const int bit = 63 - __builtin_clzll(a ^ b);
      mid = static_cast<int>(std::partition_point(code.begin() + t.begin, code.begin() + t.end,
                                                  [&](const auto& c) { return ((c.first >> bit) & 1) == 0; }) -
                             code.begin());
    }
    bin[node].count = 0;
    stack.push_back({node, mid, t.end});
    stack.push_back({-1, t.begin, mid});
  }
  // Boxes bottom-up: children have larger indices than their parent.
  for (int i = static_cast<int>(bin.size()) - 1; i >= 0; --i) {
    Node& nd = bin[i];
    Bounds box;
    if (nd.count > 0) {
      for (int k = nd.first; k < nd.first + nd.count; ++k) box.Grow(items[k].lo, items[k].hi);
    } else {
      box.Grow(bin[i + 1].lo, bin[i + 1].hi);  // left child
      box.Grow(bin[nd.first].lo, bin[nd.first].hi);
    }
    for (int k = 0; k < 3; ++k) nd.lo[k] = box.lo[k], nd.hi[k] = box.hi[k];
  }
}

}  // namespace

void TriangleBvh::Impl::Build() {
  const int nf = mesh.NumFaces();
  nodes.clear();
  if (nf == 0) return;
  std::vector<Node> bin;  // binary tree
  std::vector<BuildItem> items(nf);
  ParallelFor(nf, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t ff = b; ff < e; ++ff) {
      const int f = static_cast<int>(ff);
      BuildItem& it = items[f];
      for (int k = 0; k < 3; ++k) {
        const double x = mesh.V(mesh.F(f, 0), k), y = mesh.V(mesh.F(f, 1), k),
                     z = mesh.V(mesh.F(f, 2), k);
        it.lo[k] = std::min({x, y, z});
        it.hi[k] = std::max({x, y, z});
        it.c[k] = 0.5 * it.lo[k] + 0.5 * it.hi[k];  // no overflow near +-DBL_MAX
      }
      it.face = f;
    }
  }, 8192);
  // The items themselves are partitioned (not an index array into them): the
  // binning passes then read memory in order.
  bin.reserve(std::max(1, 2 * nf));

  // Iterative build with an explicit stack of (node index, begin, end), in
  // two phases: the top of the tree serially, down to subtrees of at most
  // `defer` triangles; then those subtrees in parallel, each into its own node
  // array, appended in a fixed order. A subtree's splits depend only on its
  // own range of the items, so the tree is the serial build's at any thread
  // count, and the depth-first re-layout below makes the layout identical too.
  struct Task {
    int node, begin, end;
  };
  // Splits task's node of `out` (filled in place) and pushes its children;
  // false for a leaf.
  auto split = [&](const Task& task, std::vector<Node>& out, std::vector<Task>& stack) {
    Bounds box, cbox;
    for (int i = task.begin; i < task.end; ++i) {
      const BuildItem& it = items[i];
      box.Grow(it.lo, it.hi);
      cbox.GrowPoint(it.c);
    }
    Node& node = out[task.node];
    for (int k = 0; k < 3; ++k) node.lo[k] = box.lo[k], node.hi[k] = box.hi[k];
    const int n = task.end - task.begin;
    auto make_leaf = [&] {
      out[task.node].first = task.begin;
      out[task.node].count = n;
    };
    if (n <= 1) {
      make_leaf();
      return;
    }
    // Binned SAH over the centroid bounds, all three axes.
    int best_axis = -1, best_split = -1;
    double best_cost = INFINITY;
    for (int axis = 0; axis < 3; ++axis) {
      const double extent = cbox.hi[axis] - cbox.lo[axis];
      if (!(extent > 0.0)) continue;
      Bounds bin_box[kBins];
      int bin_count[kBins] = {};
      const Binner binner(cbox.lo[axis], extent);
      for (int i = task.begin; i < task.end; ++i) {
        const BuildItem& it = items[i];
        const int b = binner(it.c[axis]);
        bin_count[b]++;
        bin_box[b].Grow(it.lo, it.hi);
      }
      double right_area[kBins];
      int right_count[kBins];
      Bounds acc;
      int cnt = 0;
      for (int b = kBins - 1; b > 0; --b) {
        acc.Grow(bin_box[b].lo, bin_box[b].hi);
        cnt += bin_count[b];
        right_area[b] = acc.HalfArea();
        right_count[b] = cnt;
      }
      Bounds left;
      int lcnt = 0;
      for (int b = 0; b < kBins - 1; ++b) {
        left.Grow(bin_box[b].lo, bin_box[b].hi);
        lcnt += bin_count[b];
        if (lcnt == 0 || right_count[b + 1] == 0) continue;
        const double cost = left.HalfArea() * lcnt + right_area[b + 1] * right_count[b + 1];
        if (cost < best_cost) best_cost = cost, best_axis = axis, best_split = b;
      }
    }
    // Leaf when small enough and splitting does not pay (traversal cost ~ 1 triangle test).
    const double leaf_cost = box.HalfArea() * n;
    if (n <= kMaxLeaf && (best_axis < 0 || best_cost + box.HalfArea() >= leaf_cost)) {
      make_leaf();
      return;
    }
    int mid;
    if (best_axis < 0) {
      mid = task.begin + n / 2;  // all centroids coincide: split by count
    } else {
      const Binner binner(cbox.lo[best_axis], cbox.hi[best_axis] - cbox.lo[best_axis]);
      auto it = std::partition(items.begin() + task.begin, items.begin() + task.end,
                               [&](const BuildItem& item) { return binner(item.c[best_axis]) <= best_split; });
      mid = static_cast<int>(it - items.begin());
      if (mid == task.begin || mid == task.end) mid = task.begin + n / 2;
    }
    const int left = static_cast<int>(out.size());
    out.emplace_back();
    const int right = left + 1;  // children are allocated as a pair
    out.emplace_back();
    out[task.node].count = 0;
    out[task.node].first = right;
    stack.push_back({right, mid, task.end});
    stack.push_back({left, task.begin, mid});
  };
  if (morton) {
    MortonTopology(items, bin);
  } else {
    const int defer = std::max(4096, nf / 8);
    std::vector<Task> stack, deferred;
    bin.emplace_back();
    stack.push_back({0, 0, nf});
    while (!stack.empty()) {
      const Task task = stack.back();
      stack.pop_back();
      if (task.end - task.begin <= defer && task.node != 0) {
        deferred.push_back(task);
        continue;
      }
      split(task, bin, stack);
    }
    std::vector<std::vector<Node>> sub(deferred.size());
    ParallelFor(static_cast<std::int64_t>(deferred.size()), [&](std::int64_t b0, std::int64_t e0) {
      for (std::int64_t k = b0; k < e0; ++k) {
        std::vector<Node>& out = sub[k];
        out.reserve(2 * (deferred[k].end - deferred[k].begin));
        out.emplace_back();
        std::vector<Task> st{{0, deferred[k].begin, deferred[k].end}};
        while (!st.empty()) {
          const Task task = st.back();
          st.pop_back();
          split(task, out, st);
        }
      }
    }, 1);
    // Append: a subtree's node i > 0 goes to offset + i - 1, its root to the
    // deferred node; pairs stay adjacent, so right children map alike.
    for (std::size_t k = 0; k < deferred.size(); ++k) {
      const std::vector<Node>& out = sub[k];
      const int offset = static_cast<int>(bin.size());
      auto map = [&](int i) { return i == 0 ? deferred[k].node : offset + i - 1; };
      for (std::size_t i = 1; i < out.size(); ++i) {
        Node nd = out[i];
        if (nd.count == 0) nd.first = map(nd.first);
        bin.push_back(nd);
      }
      Node root = out[0];
      if (root.count == 0) root.first = map(root.first);
      bin[deferred[k].node] = root;
    }
  }
  // Depth-first re-layout of the binary tree (left child = parent + 1); the
  // Morton build emits that layout itself.
  if (!morton) {
    std::vector<Node> out;
    out.reserve(bin.size());
    std::vector<std::pair<int, int>> st;  // (old index, new index of parent to patch or -1)
    st.push_back({0, -1});
    while (!st.empty()) {
      auto [old, patch] = st.back();
      st.pop_back();
      const int idx = static_cast<int>(out.size());
      out.push_back(bin[old]);
      if (patch >= 0) out[patch].first = idx;
      if (bin[old].count == 0) {
        // Build layout: children were allocated as a pair (left, right = left + 1).
        const int old_right = bin[old].first;
        st.push_back({old_right, idx});
        st.push_back({old_right - 1, -1});
      }
    }
    bin.swap(out);
  }
  tris.resize(nf);
  face.resize(nf);
  degenerate.resize(nf);
  ParallelFor(nf, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t i = b; i < e; ++i) {
      const int f = items[i].face;
      face[i] = f;
      Tri& t = tris[i];
      for (int k = 0; k < 3; ++k) {
        t.a[k] = mesh.V(mesh.F(f, 0), k);
        t.b[k] = mesh.V(mesh.F(f, 1), k);
        t.c[k] = mesh.V(mesh.F(f, 2), k);
      }
      const Vec3 ab(t.b[0] - t.a[0], t.b[1] - t.a[1], t.b[2] - t.a[2]);
      const Vec3 ac(t.c[0] - t.a[0], t.c[1] - t.a[1], t.c[2] - t.a[2]);
      const Vec3 bc = ac - ab;
      const double l2 = std::max({ab.squaredNorm(), ac.squaredNorm(), bc.squaredNorm()});
      // Sine of the largest angle below ~1e-10: handled as three segments.
      degenerate[i] = ab.cross(ac).squaredNorm() <= 1e-20 * l2 * l2 ? 1 : 0;
    }
  }, 8192);
  for (int k = 0; k < 3; ++k) {
    origin[k] = 0.5 * (mesh.V.col(k).minCoeff() + mesh.V.col(k).maxCoeff());
    coord_scale = std::max(coord_scale, (mesh.V.col(k).array() - origin[k]).abs().maxCoeff());
  }

  // Triangle ranges of the binary nodes: a leaf's own; an inner node's spans
  // its children (left child = next node).
  const int nb = static_cast<int>(bin.size());
  std::vector<int> range_begin(nb), range_end(nb);
  for (int i = nb - 1; i >= 0; --i) {
    const Node& nd = bin[i];
    if (nd.count > 0) {
      range_begin[i] = nd.first;
      range_end[i] = nd.first + nd.count;
    } else {
      range_begin[i] = range_begin[i + 1];
      range_end[i] = range_end[nd.first];
    }
  }
  auto half_area = [&](int i) {
    const double d0 = bin[i].hi[0] - bin[i].lo[0], d1 = bin[i].hi[1] - bin[i].lo[1],
                 d2 = bin[i].hi[2] - bin[i].lo[2];
    return d0 * d1 + d1 * d2 + d2 * d0;
  };
  // Collapse into the 4-wide tree: a 4-wide node takes the two children of a
  // binary node and keeps replacing its largest inner child by that child's
  // two children while it has fewer than four. Nodes are emitted depth-first.
  struct Pending {
    int bnode;    // binary node to collapse (inner, or a leaf when the root is one)
    int node4;    // its 4-wide index
    int depth;
  };
  // The oriented boxes are fitted afterwards, in parallel (each writes its own slot).
  struct Fit {
    int node4, slot, begin, end, bnode;
  };
  std::vector<Fit> fits;
  // Run side by side below: the collapse (serial) and the binary nodes'
  // moments for the oriented boxes. Neither reads what the other writes.
  auto collapse = [&] {
    fits.reserve(nb);
    nodes.reserve(nb / 2 + 1);
    nodes.emplace_back();
    std::vector<Pending> todo{{0, 0, 1}};
    max_depth = 1;
    while (!todo.empty()) {
      const Pending pd = todo.back();
      todo.pop_back();
      int kids[4];
      int nk = 0;
      if (bin[pd.bnode].count > 0) {
        kids[nk++] = pd.bnode;  // the whole tree is one leaf
      } else {
        kids[nk++] = pd.bnode + 1;
        kids[nk++] = bin[pd.bnode].first;
        while (nk < 4) {
          int best = -1;
          double best_area = -1.0;
          for (int k = 0; k < nk; ++k) {
            if (bin[kids[k]].count == 0 && half_area(kids[k]) > best_area) {
              best = k;
              best_area = half_area(kids[k]);
            }
          }
          if (best < 0) break;
          const int c = kids[best];
          for (int k = nk; k > best + 1; --k) kids[k] = kids[k - 1];
          kids[best] = c + 1;
          kids[best + 1] = bin[c].first;
          ++nk;
        }
      }
      Node4 fill;
      for (int j = 0; j < 4; ++j) {
        for (int k = 0; k < 3; ++k) {
          fill.lo[k][j] = fill.olo[k][j] = INFINITY;
          fill.hi[k][j] = fill.ohi[k][j] = -INFINITY;
        }
        for (int k = 0; k < 9; ++k) fill.rot[k][j] = 0.0f;
        fill.child[j] = -1;
        fill.count[j] = -1;
      }
      for (int j = 0; j < nk; ++j) {
        const Node& c = bin[kids[j]];
        for (int k = 0; k < 3; ++k) {
          fill.lo[k][j] = RoundDown(c.lo[k] - origin[k]);
          fill.hi[k][j] = RoundUp(c.hi[k] - origin[k]);
        }
        fits.push_back({pd.node4, j, range_begin[kids[j]], range_end[kids[j]], kids[j]});
        if (c.count > 0) {
          fill.child[j] = c.first;
          fill.count[j] = c.count;
        } else {
          fill.count[j] = 0;
          fill.child[j] = static_cast<int>(nodes.size());
          nodes.emplace_back();
          todo.push_back({kids[j], fill.child[j], pd.depth + 1});
          max_depth = std::max(max_depth, pd.depth + 1);
        }
      }
      nodes[pd.node4] = fill;
    }
  };
  std::vector<Moments> mom;
  Corners corners;
  auto leaf_corners = [&] {
    // Leaves in triangle order: the one starting at t holds leaf_count[t].
    std::vector<std::int32_t> leaf_count(nf, 0);
    for (int i = 0; i < nb; ++i)
      if (bin[i].count > 0) leaf_count[bin[i].first] = bin[i].count;
    corners.start.assign(static_cast<std::size_t>(nf) + 1, 0);
    corners.x.reserve(static_cast<std::size_t>(nf) * 3 / 2);
    corners.y.reserve(static_cast<std::size_t>(nf) * 3 / 2);
    corners.z.reserve(static_cast<std::size_t>(nf) * 3 / 2);
    for (int t = 0; t < nf;) {
      const int n = leaf_count[t];
      if (n <= 0) throw std::logic_error("TriangleBvh: the leaves do not partition the triangles");
      const std::size_t first = corners.x.size();
      corners.start[t] = static_cast<std::int32_t>(first);
      for (int u = t; u < t + n; ++u) {
        for (const double* v : {tris[u].a, tris[u].b, tris[u].c}) {
          const double p[3] = {v[0] - origin[0], v[1] - origin[1], v[2] - origin[2]};
          bool seen = false;
          for (std::size_t k = first; k < corners.x.size() && !seen; ++k)
            seen = corners.x[k] == p[0] && corners.y[k] == p[1] && corners.z[k] == p[2];
          if (seen) continue;
          corners.x.push_back(p[0]);
          corners.y.push_back(p[1]);
          corners.z.push_back(p[2]);
        }
      }
      t += n;
    }
    corners.start[nf] = static_cast<std::int32_t>(corners.x.size());
  };
  auto moments = [&] {
    // Each binary node's moments: the leaves' from their triangles, an inner
    // node's as the sum of its children's (children have larger indices).
    mom.resize(nb);
    ParallelFor(nb, [&](std::int64_t b0, std::int64_t e0) {
      for (std::int64_t i = b0; i < e0; ++i) {
        if (bin[i].count == 0) continue;
        for (int t = bin[i].first; t < bin[i].first + bin[i].count; ++t) mom[i].Add(TriMoments(t));
      }
    }, 4096);
    for (int i = nb - 1; i >= 0; --i) {
      if (bin[i].count > 0) continue;
      mom[i] = mom[i + 1];
      mom[i].Add(mom[bin[i].first]);
    }
  };
  if (!oriented) {
    collapse();
    // The identity frame with the axis-aligned extents: the oriented bound
    // equals the axis-aligned one.
    for (const Fit& f : fits) {
      Node4& nd = nodes[f.node4];
      for (int k = 0; k < 3; ++k) {
        for (int i = 0; i < 3; ++i) nd.rot[3 * k + i][f.slot] = k == i ? 1.0f : 0.0f;
        nd.olo[k][f.slot] = nd.lo[k][f.slot];
        nd.ohi[k][f.slot] = nd.hi[k][f.slot];
      }
    }
    return;
  }
  ParallelInvoke(collapse, [&] {
    moments();
    leaf_corners();
  });
  ParallelFor(static_cast<std::int64_t>(fits.size()), [&](std::int64_t b0, std::int64_t e0) {
    for (std::int64_t k = b0; k < e0; ++k)
      FitOrientedBox(mom[fits[k].bnode], corners, fits[k].begin, fits[k].end, &nodes[fits[k].node4],
                     fits[k].slot);
  }, 64);
}

TriangleBvh::Impl::Moments TriangleBvh::Impl::TriMoments(int t) const {
  Moments mo;
  const Tri& tr = tris[t];
  const Vec3 a(tr.a[0] - origin[0], tr.a[1] - origin[1], tr.a[2] - origin[2]);
  const Vec3 b(tr.b[0] - origin[0], tr.b[1] - origin[1], tr.b[2] - origin[2]);
  const Vec3 c(tr.c[0] - origin[0], tr.c[1] - origin[1], tr.c[2] - origin[2]);
  const Vec3 n = (b - a).cross(c - a);
  for (const Vec3* v : {&a, &b, &c}) {
    const Vec3& p = *v;
    for (int k = 0; k < 3; ++k) mo.s[k] += p[k];
    mo.m[0] += p[0] * p[0], mo.m[1] += p[1] * p[1], mo.m[2] += p[2] * p[2];
    mo.m[3] += p[0] * p[1], mo.m[4] += p[0] * p[2], mo.m[5] += p[1] * p[2];
  }
  for (int k = 0; k < 3; ++k) mo.n[k] = n[k];
  mo.count = 1;
  return mo;
}

void TriangleBvh::Impl::FitOrientedBox(const Moments& mo, const Corners& corners, int begin, int end, Node4* nd,
                                       int j) const {
  // The frame: the mean area normal (thin extent for a gently curved patch)
  // and the in-plane direction of largest spread, from the moments. Any
  // orthonormal frame gives a true bound (the extents below are exact for
  // it), so the rounding of the moments only affects how tight it is.
  const double nv = 3.0 * static_cast<double>(mo.count);
  const Vec3 c(mo.s[0] / nv, mo.s[1] / nv, mo.s[2] / nv);
  Eigen::Matrix3d cov;
  cov << mo.m[0], mo.m[3], mo.m[4], mo.m[3], mo.m[1], mo.m[5], mo.m[4], mo.m[5], mo.m[2];
  cov -= nv * c * c.transpose();
  const Vec3 nsum(mo.n[0], mo.n[1], mo.n[2]);
  Vec3 n;
  if (nsum.norm() > 0.0) {
    n = nsum.normalized();
  } else {  // closed or degenerate patch: direction of least spread
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
    es.computeDirect(cov);
    n = es.eigenvectors().col(0);
    if (!(n.norm() > 0.5)) n = Vec3::UnitX();
    n.normalize();
  }
  // The in-plane direction of largest spread: the principal axis of the
  // 2 x 2 form [a b; b c] of cov in a basis (e1, e2) of the plane, at angle
  // atan2(2b, a - c) / 2 from e1.
  const Vec3 e1 = n.unitOrthogonal(), e2 = n.cross(e1);
  const Vec3 ce1 = cov * e1, ce2 = cov * e2;
  const double a = e1.dot(ce1), b = e1.dot(ce2), cc = e2.dot(ce2);
  const double theta = 0.5 * std::atan2(2.0 * b, a - cc);
  Vec3 t1 = std::isfinite(theta) ? Vec3(std::cos(theta) * e1 + std::sin(theta) * e2) : e1;
  t1 -= n * n.dot(t1);
  if (!(t1.norm() > 1e-6)) t1 = e1;
  t1.normalize();
  const Vec3 axes[3] = {n, t1, n.cross(t1)};
  // The frame is stored in float; extents are exact (in double) for the
  // float frame, then rounded outward. One pass over the leaves' distinct
  // corners (the same extremes as over every triangle's corners).
  double r[3][3];
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < 3; ++i) r[k][i] = nd->rot[3 * k + i][j] = static_cast<float>(axes[k][i]);
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  const double* cx = corners.x.data();
  const double* cy = corners.y.data();
  const double* cz = corners.z.data();
  int v = corners.start[begin];
  const int vend = corners.start[end];
#if defined(__SSE2__)
  // Two corners per step, each projection the scalar one's (r0 p0 + r1 p1) + r2 p2.
  if (vend - v >= 2) {
    __m128d l[3], h[3], rv[3][3];
    for (int k = 0; k < 3; ++k) {
      l[k] = _mm_set1_pd(INFINITY);
      h[k] = _mm_set1_pd(-INFINITY);
      for (int i = 0; i < 3; ++i) rv[k][i] = _mm_set1_pd(r[k][i]);
    }
    for (; v + 2 <= vend; v += 2) {
      const __m128d px = _mm_loadu_pd(cx + v), py = _mm_loadu_pd(cy + v), pz = _mm_loadu_pd(cz + v);
      for (int k = 0; k < 3; ++k) {
        const __m128d d =
            _mm_add_pd(_mm_add_pd(_mm_mul_pd(rv[k][0], px), _mm_mul_pd(rv[k][1], py)), _mm_mul_pd(rv[k][2], pz));
        l[k] = _mm_min_pd(l[k], d);
        h[k] = _mm_max_pd(h[k], d);
      }
    }
    for (int k = 0; k < 3; ++k) {
      alignas(16) double a[2], b[2];
      _mm_store_pd(a, l[k]);
      _mm_store_pd(b, h[k]);
      lo[k] = std::min(a[0], a[1]);
      hi[k] = std::max(b[0], b[1]);
    }
  }
#endif
  for (; v < vend; ++v) {
    const double p[3] = {cx[v], cy[v], cz[v]};
    for (int k = 0; k < 3; ++k) {
      const double d = r[k][0] * p[0] + r[k][1] * p[1] + r[k][2] * p[2];
      lo[k] = std::min(lo[k], d);
      hi[k] = std::max(hi[k], d);
    }
  }
  for (int k = 0; k < 3; ++k) {
    nd->olo[k][j] = RoundDown(lo[k]);
    nd->ohi[k][j] = RoundUp(hi[k]);
  }
}

TriangleBvh::Hit TriangleBvh::Impl::Query(const double* q, double max_sq, int* tri) const {
  struct Entry {
    std::int32_t child, count;
    double lb;
  };
  // A 4-wide node pushes at most 3 entries per level.
  const int need = 3 * max_depth + 4;
  Entry small[192];
  std::vector<Entry> large;
  Entry* stack = small;
  if (need > 192) {
    large.resize(need);
    stack = large.data();
  }
  return oriented ? QueryWith<true>(q, max_sq, stack, tri) : QueryWith<false>(q, max_sq, stack, tri);
}

template <bool Oriented, class Entry>
TriangleBvh::Hit TriangleBvh::Impl::QueryWith(const double* q, double max_sq, Entry* stack,
                                               int* tri) const {
  TriangleBvh::Hit hit;
  if (tri) *tri = -1;
  if (nodes.empty()) return hit;
  double best = max_sq;
  int best_face = -1, best_tri = -1;
  double best_pt[3] = {0, 0, 0};
  const double qr[3] = {q[0] - origin[0], q[1] - origin[1], q[2] - origin[2]};
  const float qf[3] = {static_cast<float>(qr[0]), static_cast<float>(qr[1]), static_cast<float>(qr[2])};
  // Rounding allowance of the float bounds (absolute): q to float, rot * q
  // and the subtractions, all within a few float ulps of |q| + |mesh|.
  const double qnorm = std::abs(qr[0]) + std::abs(qr[1]) + std::abs(qr[2]);
  // Beyond float range (or NaN) the bounds degrade to 0: every node is opened.
  const float margin = qnorm < 1e30 ? static_cast<float>(1e-6 * (qnorm + coord_scale)) : INFINITY;
  int sp = 0;
  stack[sp++] = {0, 0, 0.0};
  while (sp > 0) {
    const Entry e = stack[--sp];
    if (e.lb > best * kPruneSlack) continue;
    if (e.count > 0) {
      for (int i = e.child, end = e.child + e.count; i < end; ++i) {
        double p[3];
        const double d = TriSqDist(i, q, p);
        if (d < best || (d == best && (best_face < 0 || face[i] < best_face))) {
          best = d;
          best_face = face[i];
          best_tri = i;
          best_pt[0] = p[0], best_pt[1] = p[1], best_pt[2] = p[2];
        }
      }
      continue;
    }
    const Node4& n = nodes[e.child];
    alignas(16) float lb[4];
    ChildLowerBounds<Oriented>(n, qf, margin, lb);
    // Children within reach, sorted nearest first (pushed farthest first).
    const double lim = best * kPruneSlack;
    Entry kids[4];
    int nk = 0;
    for (int j = 0; j < 4; ++j) {
      if (n.count[j] < 0 || static_cast<double>(lb[j]) > lim) continue;
      Entry k{n.child[j], n.count[j], static_cast<double>(lb[j])};
      int pos = nk++;
      while (pos > 0 && kids[pos - 1].lb < k.lb) {
        kids[pos] = kids[pos - 1];
        --pos;
      }
      kids[pos] = k;
    }
    for (int j = 0; j < nk; ++j) stack[sp++] = kids[j];
  }
  if (best_face >= 0) {
    hit.sq_dist = best;
    hit.face = best_face;
    hit.point = Vec3(best_pt[0], best_pt[1], best_pt[2]);
    if (tri) *tri = best_tri;
  }
  return hit;
}

TriangleBvh::TriangleBvh(const Mesh& mesh) : TriangleBvh(mesh, BuildKind::kSahOriented) {}

TriangleBvh::TriangleBvh(const Mesh& mesh, bool oriented_boxes)
    : TriangleBvh(mesh, oriented_boxes ? BuildKind::kSahOriented : BuildKind::kMortonAxisAligned) {}

TriangleBvh::TriangleBvh(const Mesh& mesh, BuildKind build) : impl_(std::make_unique<Impl>()) {
  CheckMeshIndices(mesh, "TriangleBvh", /*finite=*/true);
  impl_->mesh = mesh;
  impl_->oriented = build != BuildKind::kMortonAxisAligned;
  impl_->morton = build != BuildKind::kSahOriented;
  impl_->Build();
}
TriangleBvh::~TriangleBvh() = default;
TriangleBvh::TriangleBvh(TriangleBvh&&) noexcept = default;
TriangleBvh& TriangleBvh::operator=(TriangleBvh&&) noexcept = default;

const Mesh& TriangleBvh::mesh() const { return impl_->mesh; }

TriangleBvh::Hit TriangleBvh::Closest(const Vec3& q, double max_sq_dist) const {
  const double p[3] = {q.x(), q.y(), q.z()};
  return impl_->Query(p, max_sq_dist);
}

void TriangleBvh::ClosestPoints(const MatrixX3d& Q, VectorXd* sq_dist, MatrixX3d* points,
                                Eigen::VectorXi* faces) const {
  const std::int64_t n = Q.rows();
  if (sq_dist) sq_dist->resize(n);
  if (points) points->resize(n, 3);
  if (faces) faces->resize(n);
  // Morton order makes consecutive queries neighbours whatever the input
  // order (3.4x faster on random points, 10% on grid order).
  const std::vector<int> order = MortonOrder(Q);
  ParallelFor(
      n,
      [&](std::int64_t begin, std::int64_t end) {
        // Warm start: the previous query's closest triangle, evaluated at q,
        // bounds d(q) from above and is usually within a hair of it
        // (neighbours in Morton order). Inflated slightly against rounding;
        // the answer does not depend on it.
        int prev_tri = -1;
        for (std::int64_t s = begin; s < end; ++s) {
          const std::int64_t i = order[s];
          const double q[3] = {Q(i, 0), Q(i, 1), Q(i, 2)};
          TriangleBvh::Hit hit;
          int tri = -1;
          if (prev_tri >= 0) {
            double p[3];
            const double ub = impl_->TriSqDist(prev_tri, q, p);
            hit = impl_->Query(q, ub * (1.0 + 1e-9) + 1e-300, &tri);
          }
          if (hit.face < 0) hit = impl_->Query(q, INFINITY, &tri);
          prev_tri = tri;
          if (sq_dist) (*sq_dist)[i] = hit.sq_dist;
          if (points) points->row(i) = hit.point.transpose();
          if (faces) (*faces)[i] = hit.face;
        }
      },
      256);
}

}  // namespace arcs
