#include "framework/rfta/component_filter.h"

#include "framework/geometry/builtin_shapes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace arcs {
namespace {

const Vec3 kBigCenter(-0.45, 0, 0), kSmallCenter(0.5, 0, 0);
constexpr double kBigR = 0.3, kSmallR = 0.12;

// Exact SDF of two disjoint balls (and, with extra_r > 0, a third of that
// radius at extra_c) at the (n+1)^3 nodes of [-1, 1]^3.
SdfSamples TwoBalls(int n, double extra_r = 0, const Vec3& extra_c = Vec3::Zero()) {
  SdfSamples s;
  s.dim = 3;
  const int m = n + 1;
  s.points.resize(static_cast<Eigen::Index>(m) * m * m, 3);
  s.values.resize(s.points.rows());
  Eigen::Index t = 0;
  for (int k = 0; k < m; ++k)
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i, ++t) {
        const Vec3 p(-1.0 + 2.0 * i / n, -1.0 + 2.0 * j / n, -1.0 + 2.0 * k / n);
        s.points.row(t) = p.transpose();
        s.values[t] = std::min((p - kBigCenter).norm() - kBigR, (p - kSmallCenter).norm() - kSmallR);
        if (extra_r > 0) s.values[t] = std::min(s.values[t], (p - extra_c).norm() - extra_r);
      }
  return s;
}

Mesh Concat(const std::vector<Mesh>& parts) {
  Mesh out;
  int nv = 0, nf = 0;
  for (const Mesh& m : parts) nv += m.NumVertices(), nf += m.NumFaces();
  out.V.resize(nv, 3);
  out.F.resize(nf, 3);
  int v0 = 0, f0 = 0;
  for (const Mesh& m : parts) {
    out.V.middleRows(v0, m.NumVertices()) = m.V;
    out.F.middleRows(f0, m.NumFaces()) = m.F.array() + v0;
    v0 += m.NumVertices();
    f0 += m.NumFaces();
  }
  return out;
}

// A real part reconstructed too fat (the small ball at 1.25x its radius: every
// vertex inside the spheres of the samples around it) is a candidate but
// stays, since its samples have no other surface near them; a bubble in the
// free space (inside the spheres too) fits no sample and goes.
TEST(ComponentFilter, KeepsAFatRealPartAndDropsABubble) {
  const SdfSamples samples = TwoBalls(20);
  const Mesh big = MakeIcosphere(kBigR, 3, kBigCenter);
  const Mesh fat_small = MakeIcosphere(1.25 * kSmallR, 3, kSmallCenter);
  const Mesh bubble = MakeIcosphere(0.02, 1, Vec3(0.0, 0.65, 0.0));
  Mesh m = Concat({big, fat_small, bubble});
  const ComponentFilterStats st = DropInfeasibleComponents(&m, samples, 1e-4);
  EXPECT_EQ(st.components, 3);
  EXPECT_EQ(st.dropped, 1);
  EXPECT_EQ(st.kept_by_fit, 1);
  EXPECT_EQ(m.NumFaces(), big.NumFaces() + fat_small.NumFaces());
  EXPECT_EQ(m.NumVertices(), big.NumVertices() + fat_small.NumVertices());
  // What is kept is in its order: the big ball's vertices first.
  EXPECT_EQ(m.V.topRows(big.NumVertices()), big.V);
}

// The exact surface: nothing is a candidate, nothing changes.
TEST(ComponentFilter, ExactSurfaceIsUntouched) {
  const SdfSamples samples = TwoBalls(20);
  Mesh m = Concat({MakeIcosphere(kBigR, 3, kBigCenter), MakeIcosphere(kSmallR, 3, kSmallCenter)});
  const Mesh before = m;
  const ComponentFilterStats st = DropInfeasibleComponents(&m, samples, 1e-3);
  EXPECT_EQ(st.components, 2);
  EXPECT_EQ(st.dropped, 0);
  EXPECT_EQ(st.kept_by_fit, 0);
  EXPECT_EQ(m.F, before.F);
}

// Small components (DropSmallComponents). The samples' spacing is 0.1 here.
// A blob 0.03 across standing 0.005 off the big ball, which the samples do
// not have: no sample's fit needs it (their misfit only falls without it),
// so it goes; the small ball is real, 0.24 across, above the extent, and
// stays whatever its fit.
TEST(SmallComponents, DropsABlobTheFitDoesNotNeed) {
  const SdfSamples samples = TwoBalls(20);
  const Mesh big = MakeIcosphere(kBigR, 3, kBigCenter), small = MakeIcosphere(kSmallR, 3, kSmallCenter);
  const Mesh blob = MakeIcosphere(0.015, 1, kBigCenter + Vec3(0, kBigR + 0.02, 0));
  Mesh m = Concat({big, blob, small});
  const SmallComponentStats st = DropSmallComponents(&m, samples, 0.05, 0.05 * 0.05);
  EXPECT_EQ(st.components, 3);
  EXPECT_EQ(st.candidates, 1);
  EXPECT_EQ(st.dropped, 1);
  EXPECT_LE(st.misfit_added, 0.0) << "the blob only made the fit worse";
  EXPECT_EQ(m.NumFaces(), big.NumFaces() + small.NumFaces());
  ASSERT_EQ(m.NumVertices(), big.NumVertices() + small.NumVertices());
  EXPECT_EQ(m.V.topRows(big.NumVertices()), big.V);
  EXPECT_EQ(m.V.bottomRows(small.NumVertices()), small.V);
}

// A real part is a candidate when the extent allows it, but its samples have
// no other surface near them: removing it would cost far more than the
// budget, so it stays, while the blob beside it goes.
TEST(SmallComponents, KeepsAPartTheFitNeeds) {
  const SdfSamples samples = TwoBalls(20);
  const Mesh big = MakeIcosphere(kBigR, 3, kBigCenter), small = MakeIcosphere(kSmallR, 3, kSmallCenter);
  Mesh m = Concat({big, small, MakeIcosphere(0.015, 1, kBigCenter + Vec3(0, kBigR + 0.02, 0))});
  const SmallComponentStats st = DropSmallComponents(&m, samples, 1.0, 0.05 * 0.05);
  EXPECT_EQ(st.candidates, 2);
  EXPECT_EQ(st.dropped, 1);
  EXPECT_EQ(m.NumFaces(), big.NumFaces() + small.NumFaces());
}

// A tiny ball that the samples do have (a third ball in their SDF, 0.03
// across, 0.06 off the big one): without it its samples' misfit rises by
// about that gap. The budget decides: none keeps it, a generous one lets it
// go and reports what it added. Nothing at all happens with no extent.
TEST(SmallComponents, TheBudgetDecidesForAPieceTheSamplesHave) {
  const Vec3 tiny_c = kBigCenter + Vec3(0, kBigR + 0.075, 0);
  const SdfSamples samples = TwoBalls(20, 0.015, tiny_c);
  const Mesh parts = Concat({MakeIcosphere(kBigR, 3, kBigCenter), MakeIcosphere(kSmallR, 3, kSmallCenter),
                             MakeIcosphere(0.015, 2, tiny_c)});
  Mesh kept = parts;
  const SmallComponentStats none = DropSmallComponents(&kept, samples, 0.05, 0.0);
  EXPECT_EQ(none.candidates, 1);
  EXPECT_EQ(none.dropped, 0);
  EXPECT_EQ(kept.F, parts.F);
  Mesh gone = parts;
  const SmallComponentStats generous = DropSmallComponents(&gone, samples, 0.05, 1.0);
  EXPECT_EQ(generous.dropped, 1);
  EXPECT_GT(generous.misfit_added, 1e-4) << "its samples were served by it";
  EXPECT_LT(generous.misfit_added, 1.0);
  Mesh untouched = parts;
  EXPECT_EQ(DropSmallComponents(&untouched, samples, 0.0, 1.0).dropped, 0);
  EXPECT_EQ(untouched.F, parts.F);
}

}  // namespace
}  // namespace arcs
