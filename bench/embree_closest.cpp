// Embree 3 rtcPointQuery closest-point back-end of spatial_bench. Embree stores
// float vertices; the per-triangle callback computes the distance in double
// from the original double vertices.
#include "bench_backends.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>
#include <vector>

namespace arcs::bench {
namespace {
double Now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

struct MeshRef {
  const double* V;
  const int* F;
};

struct QueryState {
  const MeshRef* mesh;
  double q[3];
  double best_sq;
};

double Dot(const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// Closest point on triangle (Voronoi regions), squared distance.
double TriSq(const double* a, const double* b, const double* c, const double* p) {
  double ab[3], ac[3], ap[3], bp[3], cp[3], r[3];
  for (int k = 0; k < 3; ++k) ab[k] = b[k] - a[k], ac[k] = c[k] - a[k], ap[k] = p[k] - a[k];
  auto sq = [&](const double* x) {
    const double d[3] = {p[0] - x[0], p[1] - x[1], p[2] - x[2]};
    return Dot(d, d);
  };
  const double d1 = Dot(ab, ap), d2 = Dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return sq(a);
  for (int k = 0; k < 3; ++k) bp[k] = p[k] - b[k];
  const double d3 = Dot(ab, bp), d4 = Dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return sq(b);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    for (int k = 0; k < 3; ++k) r[k] = a[k] + v * ab[k];
    return sq(r);
  }
  for (int k = 0; k < 3; ++k) cp[k] = p[k] - c[k];
  const double d5 = Dot(ab, cp), d6 = Dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return sq(c);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    for (int k = 0; k < 3; ++k) r[k] = a[k] + w * ac[k];
    return sq(r);
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    for (int k = 0; k < 3; ++k) r[k] = b[k] + w * (c[k] - b[k]);
    return sq(r);
  }
  const double den = 1.0 / (va + vb + vc);
  const double v = vb * den, w = vc * den;
  for (int k = 0; k < 3; ++k) r[k] = a[k] + ab[k] * v + ac[k] * w;
  return sq(r);
}

bool PointQueryFunc(RTCPointQueryFunctionArguments* args) {
  auto* st = static_cast<QueryState*>(args->userPtr);
  const int f = static_cast<int>(args->primID);
  const double* V = st->mesh->V;
  const int* F = st->mesh->F;
  const double d = TriSq(V + 3 * F[3 * f], V + 3 * F[3 * f + 1], V + 3 * F[3 * f + 2], st->q);
  if (d < st->best_sq) {
    st->best_sq = d;
    // Shrink the search sphere; inflate a little since Embree's boxes are float.
    args->query->radius = static_cast<float>(std::sqrt(d) * (1.0 + 1e-6) + 1e-7);
    return true;
  }
  return false;
}
}  // namespace

double EmbreeClosestSqDists(const double* V, int nv, const int* F, int nf, const double* Q,
                            std::int64_t nq, int threads, double* out_sq, double* build_seconds) {
  const double t0 = Now();
  RTCDevice device = rtcNewDevice("threads=1");
  RTCScene scene = rtcNewScene(device);
  RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vb = static_cast<float*>(
      rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), nv));
  for (int i = 0; i < 3 * nv; ++i) vb[i] = static_cast<float>(V[i]);
  auto* ib = static_cast<unsigned*>(
      rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), nf));
  for (int i = 0; i < 3 * nf; ++i) ib[i] = static_cast<unsigned>(F[i]);
  rtcCommitGeometry(geom);
  rtcAttachGeometry(scene, geom);
  rtcReleaseGeometry(geom);
  rtcCommitScene(scene);
  const double t1 = Now();
  if (build_seconds) *build_seconds = t1 - t0;
  const MeshRef mesh{V, F};
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t) {
    pool.emplace_back([&, t] {
      const std::int64_t b = nq * t / threads, e = nq * (t + 1) / threads;
      for (std::int64_t i = b; i < e; ++i) {
        QueryState st{&mesh, {Q[3 * i], Q[3 * i + 1], Q[3 * i + 2]}, INFINITY};
        RTCPointQuery query;
        query.x = static_cast<float>(st.q[0]);
        query.y = static_cast<float>(st.q[1]);
        query.z = static_cast<float>(st.q[2]);
        query.time = 0.f;
        query.radius = INFINITY;
        RTCPointQueryContext ctx;
        rtcInitPointQueryContext(&ctx);
        rtcPointQuery(scene, &query, &ctx, PointQueryFunc, &st);
        out_sq[i] = st.best_sq;
      }
    });
  }
  for (auto& th : pool) th.join();
  const double t2 = Now();
  rtcReleaseScene(scene);
  rtcReleaseDevice(device);
  return t2 - t1;
}

}  // namespace arcs::bench
