// Trilateration for Alg. 2 (make feasible): the common points of three
// spheres, split so that a ball paired with many others around the same
// sphere shares its part, and a two-lane form for the pair loop. Internal to
// framework/rfta (arc_projector.cpp); a header so that the test can hold the
// two-lane form to the scalar one bit for bit.
#pragma once

#include "framework/types.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace arcs::trilateration {

// The (up to two) common points of three spheres, by trilateration in the
// frame of the three centres (Fang 1986). 0 when the centres are (nearly)
// collinear or the spheres have no common point. In two parts: what depends
// on the first two spheres only (Alg. 2 pairs one ball with many others
// around the same sphere), then the third; the arithmetic is the one-call
// form's, operation for operation.
struct TrilaterationBase {
  Vec3 ex;       // unit p1 -> p2 (when d > 0)
  double d;      // |p2 - p1|
  double x = 0;  // the common points' coordinate along ex (when d > 0)
};
inline TrilaterationBase TrilaterateBase(const Vec3& p1, double r1, const Vec3& p2, double r2) {
  TrilaterationBase b;
  b.ex = p2 - p1;
  b.d = b.ex.norm();
  if (b.d > 0.0) {  // else TrilaterateWith answers 0 before reading ex or x
    b.ex /= b.d;
    b.x = (r1 * r1 - r2 * r2 + b.d * b.d) / (2.0 * b.d);
  }
  return b;
}
inline int TrilaterateWith(const TrilaterationBase& b, const Vec3& p1, double r1, double r2, const Vec3& p3,
                           double r3, Vec3 out[2]) {
  const double scale = std::max({r1, r2, r3});
  if (!(b.d > 1e-12 * scale)) return 0;
  const Vec3& ex = b.ex;
  const Vec3 t = p3 - p1;
  const double i = ex.dot(t);
  Vec3 ey = t - i * ex;
  const double j = ey.norm();
  if (!(j > 1e-12 * scale)) return 0;
  ey /= j;
  const Vec3 ez = ex.cross(ey);
  const double x = b.x;
  const double y = (r1 * r1 - r3 * r3 + i * i + j * j) / (2.0 * j) - (i / j) * x;
  double z2 = r1 * r1 - x * x - y * y;
  if (z2 < 0.0) {
    if (z2 < -1e-12 * r1 * r1) return 0;
    z2 = 0.0;  // tangent within rounding
  }
  const double z = std::sqrt(z2);
  const Vec3 base = p1 + x * ex + y * ey;
  out[0] = base + z * ez;
  out[1] = base - z * ez;
  return 2;
}
// TrilaterateWith for two first-pair frames at once (b[0] with radius r2[0],
// b[1] with r2[1]; the same p1, r1, p3, r3): out[k] and n[k] are exactly
// what TrilaterateWith(b[k], p1, r1, r2[k], p3, r3, out[k]) gives. Each
// SSE2 lane does the scalar form's operations in its order (Eigen's dot and
// squared norm sum left to right, (v0 + v1) + v2), and packed division and
// square root round as the scalar ones do. Alg. 2's pair loop is bound by
// these divisions and roots.
inline void TrilaterateWith2(const TrilaterationBase* const b[2], const Vec3& p1, double r1, const double r2[2],
                             const Vec3& p3, double r3, Vec3 out[2][2], int n[2]) {
#if defined(__SSE2__)
  bool live[2];
  double scale[2];
  for (int k = 0; k < 2; ++k) {
    scale[k] = std::max({r1, r2[k], r3});
    live[k] = b[k]->d > 1e-12 * scale[k];
  }
  if (!live[0] && !live[1]) {
    n[0] = n[1] = 0;
    return;
  }
  auto pair = [](double lo, double hi) { return _mm_set_pd(hi, lo); };
  const Vec3 t = p3 - p1;
  __m128d ex[3];
  for (int a = 0; a < 3; ++a) ex[a] = pair(b[0]->ex[a], b[1]->ex[a]);
  const __m128d t0 = _mm_set1_pd(t[0]), t1 = _mm_set1_pd(t[1]), t2 = _mm_set1_pd(t[2]);
  const __m128d i = _mm_add_pd(_mm_add_pd(_mm_mul_pd(ex[0], t0), _mm_mul_pd(ex[1], t1)), _mm_mul_pd(ex[2], t2));
  __m128d ey[3] = {_mm_sub_pd(t0, _mm_mul_pd(i, ex[0])), _mm_sub_pd(t1, _mm_mul_pd(i, ex[1])),
                   _mm_sub_pd(t2, _mm_mul_pd(i, ex[2]))};
  const __m128d j = _mm_sqrt_pd(_mm_add_pd(_mm_add_pd(_mm_mul_pd(ey[0], ey[0]), _mm_mul_pd(ey[1], ey[1])),
                                           _mm_mul_pd(ey[2], ey[2])));
  for (int a = 0; a < 3; ++a) ey[a] = _mm_div_pd(ey[a], j);
  const __m128d ez[3] = {_mm_sub_pd(_mm_mul_pd(ex[1], ey[2]), _mm_mul_pd(ex[2], ey[1])),
                         _mm_sub_pd(_mm_mul_pd(ex[2], ey[0]), _mm_mul_pd(ex[0], ey[2])),
                         _mm_sub_pd(_mm_mul_pd(ex[0], ey[1]), _mm_mul_pd(ex[1], ey[0]))};
  const __m128d x = pair(b[0]->x, b[1]->x);
  const __m128d r1s = _mm_set1_pd(r1 * r1), r3s = _mm_set1_pd(r3 * r3);
  const __m128d y = _mm_sub_pd(
      _mm_div_pd(_mm_add_pd(_mm_add_pd(_mm_sub_pd(r1s, r3s), _mm_mul_pd(i, i)), _mm_mul_pd(j, j)),
                 _mm_mul_pd(_mm_set1_pd(2.0), j)),
      _mm_mul_pd(_mm_div_pd(i, j), x));
  __m128d z2 = _mm_sub_pd(_mm_sub_pd(r1s, _mm_mul_pd(x, x)), _mm_mul_pd(y, y));
  alignas(16) double jv[2], z2v[2];
  _mm_store_pd(jv, j);
  _mm_store_pd(z2v, z2);
  for (int k = 0; k < 2; ++k)
    live[k] = live[k] && jv[k] > 1e-12 * scale[k] && !(z2v[k] < 0.0 && z2v[k] < -1e-12 * r1 * r1);
  if (!live[0] && !live[1]) {
    n[0] = n[1] = 0;
    return;
  }
  z2 = _mm_andnot_pd(_mm_cmplt_pd(z2, _mm_setzero_pd()), z2);  // tangent within rounding: 0
  const __m128d z = _mm_sqrt_pd(z2);
  alignas(16) double lo[3][2], hi[3][2];
  for (int a = 0; a < 3; ++a) {
    const __m128d base = _mm_add_pd(_mm_add_pd(_mm_set1_pd(p1[a]), _mm_mul_pd(x, ex[a])), _mm_mul_pd(y, ey[a]));
    const __m128d zz = _mm_mul_pd(z, ez[a]);
    _mm_store_pd(lo[a], _mm_add_pd(base, zz));
    _mm_store_pd(hi[a], _mm_sub_pd(base, zz));
  }
  for (int k = 0; k < 2; ++k) {
    n[k] = live[k] ? 2 : 0;
    if (!live[k]) continue;
    out[k][0] = Vec3(lo[0][k], lo[1][k], lo[2][k]);
    out[k][1] = Vec3(hi[0][k], hi[1][k], hi[2][k]);
  }
#else
  for (int k = 0; k < 2; ++k) n[k] = TrilaterateWith(*b[k], p1, r1, r2[k], p3, r3, out[k]);
#endif
}
inline int Trilaterate(const Vec3& p1, double r1, const Vec3& p2, double r2, const Vec3& p3, double r3,
                Vec3 out[2]) {
  return TrilaterateWith(TrilaterateBase(p1, r1, p2, r2), p1, r1, r2, p3, r3, out);
}

}  // namespace arcs::trilateration
