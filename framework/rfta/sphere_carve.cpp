#include "framework/rfta/sphere_carve.h"

#include "framework/error.h"
#include "framework/rfta/sphere_set.h"
#include "framework/rfta/sphere_tree.h"
#include "framework/util/parallel.h"

#include <algorithm>
#include <memory>
#include <string>

namespace arcs {

double CarveMargin(const SdfSamples& samples, double tol_unit, double fraction) {
  const double tol = tol_unit * ComputeUnitFrame(samples).scale;
  return fraction > 0 ? std::max(tol, fraction * SampleSpacing(samples)) : tol;
}

CarveField OutsideSpheresCarve(const SdfSamples& samples, double margin) {
  if (samples.dim != 3)
    throw Error("carve outside_spheres: needs 3D SDF samples, got " + std::to_string(samples.dim) + "D");
  if (!(margin >= 0)) throw Error("carve outside_spheres: margin must be >= 0");
  std::int64_t count = 0;
  for (std::int64_t i = 0; i < samples.Size(); ++i) count += samples.values[i] > 0;
  if (count == 0) throw Error("carve outside_spheres: no sample is positive (no ball certifies empty space)");
  MatrixX3d centers(count, 3);
  VectorXd radii(count);
  std::vector<int> ids(static_cast<std::size_t>(count));
  std::int64_t k = 0;
  for (std::int64_t i = 0; i < samples.Size(); ++i) {
    if (!(samples.values[i] > 0)) continue;
    centers.row(k) = samples.points.row(i).head<3>();
    radii[k] = samples.values[i];
    ids[static_cast<std::size_t>(k)] = static_cast<int>(i);
    ++k;
  }
  auto tree = std::make_shared<const SphereTree>(centers, radii, ids);
  CarveField f;
  // Containment (the query the tree is built for) decides; the distance to
  // the union, slower near the surface where thousands of balls are almost
  // tangent, is computed only where a vertex is placed (session 41: bunny_fixed
  // n = 40's final step 0.84 -> 4.2 s when every node asked for it).
  f.claims = [tree, margin](const std::vector<Vec3>& x, std::vector<char>& inside) {
    inside.assign(x.size(), 0);
    ParallelFor(static_cast<std::int64_t>(x.size()), [&](std::int64_t b, std::int64_t e) {
      for (std::int64_t i = b; i < e; ++i) inside[i] = tree->AnyContains(x[i], -margin, /*ignore_id=*/-1);
    }, 256);
  };
  f.value = [tree, margin](const Vec3& x) { return -tree->DistanceToUnion(x, 1.0) - margin; };
  return f;
}

}  // namespace arcs
