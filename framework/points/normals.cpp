#include "framework/points/normals.h"

#include "framework/error.h"
#include "framework/points/backends.h"

#include <algorithm>

namespace arcs {

void NormalOptions::Check() const {
  ARCS_CHECK_OPTION(k >= 3 && k <= 1000, "k", k, "in [3, 1000]");
  if (method != "jet" && method != "pca") throw OptionError("method = " + method + ": must be one of {jet, pca}");
  if (orientation != "mst" && orientation != "centroid" && orientation != "none")
    throw OptionError("orientation = " + orientation + ": must be one of {mst, centroid, none}");
}

MatrixX3d EstimateNormals(const MatrixX3d& P, const NormalOptions& o, NormalReport* report) {
  o.Check();
  const int n = static_cast<int>(P.rows());
  if (n < 3) throw Error("estimate_normals: needs at least 3 points, got " + std::to_string(n));
  for (int i = 0; i < n; ++i)
    if (!P.row(i).allFinite())
      throw Error("estimate_normals: point " + std::to_string(i) + " has a non-finite coordinate");
  const int k = std::min(o.k, n - 1);
  MatrixX3d N = points_detail::CgalEstimateNormals(P, k, o.method == "jet");
  // A degenerate neighbourhood (all neighbours coincide) can give a zero or
  // NaN normal: replace by +z so that later stages see a unit vector.
  for (int i = 0; i < n; ++i) {
    const double len = N.row(i).norm();
    if (std::isfinite(len) && len > 0) N.row(i) /= len;
    else N.row(i) << 0, 0, 1;
  }
  const Vec3 centroid = P.colwise().mean().transpose();
  auto away_from_centroid = [&](int i) {
    if (N.row(i).dot(P.row(i) - centroid.transpose()) < 0) N.row(i) *= -1.0;
  };
  NormalReport rep;
  if (o.orientation == "mst") {
    const std::vector<char> oriented = points_detail::CgalMstOrientNormals(P, &N, k);
    for (int i = 0; i < n; ++i)
      if (!oriented[i]) {
        ++rep.unoriented;
        away_from_centroid(i);
      }
  } else if (o.orientation == "centroid") {
    for (int i = 0; i < n; ++i) away_from_centroid(i);
  }
  if (report) *report = rep;
  return N;
}

}  // namespace arcs
