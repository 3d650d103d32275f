#include "framework/sdfmesh/sdf_input.h"

#include "framework/error.h"

#include <cmath>

namespace arcs {

void CheckSdfToMeshInput(const SdfSamples& s, const std::string& who, bool need_grid, double isovalue) {
  const std::string p = who + ": ";
  if (s.dim != 3)
    throw Error(p + "needs 3D SDF samples (got dim " + std::to_string(s.dim) + ")");
  if (s.points.rows() != s.values.size())
    throw Error(p + "the SDF samples have " + std::to_string(s.points.rows()) + " points but " +
                std::to_string(s.values.size()) + " values");
  if (s.points.rows() > 0 && s.points.cols() < 3)
    throw Error(p + "the SDF sample points have " + std::to_string(s.points.cols()) + " columns, need 3");
  if (s.Size() < 2) throw Error(p + "needs at least 2 SDF samples (got " + std::to_string(s.Size()) + ")");
  if (need_grid) {
    if (!s.grid)
      throw Error(p + "needs samples on a regular grid (e.g. from sdf_grid or a grid .npy), got scattered samples");
    const GridInfo& g = *s.grid;
    if (g.dim != 3) throw Error(p + "needs a 3D grid (got a " + std::to_string(g.dim) + "D grid)");
    for (int a = 0; a < 3; ++a) {
      if (g.dims[a] < 2)
        throw Error(p + "the grid has " + std::to_string(g.dims[a]) + " node(s) along axis " + std::to_string(a) +
                    "; at least 2 are needed");
      if (!(g.max[a] > g.min[a]) || !std::isfinite(g.max[a] - g.min[a]))
        throw Error(p + "the grid's extent along axis " + std::to_string(a) + " is not positive and finite");
    }
    if (g.NumNodes() != s.values.size())
      throw Error(p + "the grid has " + std::to_string(g.NumNodes()) + " nodes but there are " +
                  std::to_string(s.values.size()) + " values");
  }
  std::int64_t below = 0, above = 0;
  for (std::int64_t i = 0; i < s.Size(); ++i) {
    if (!std::isfinite(s.values[i]))
      throw Error(p + "SDF sample " + std::to_string(i) + " has a non-finite value (" + std::to_string(s.values[i]) + ")");
    for (int k = 0; k < 3; ++k)
      if (!std::isfinite(s.points(i, k)))
        throw Error(p + "SDF sample " + std::to_string(i) + " has a non-finite coordinate");
    (s.values[i] < isovalue ? below : above)++;
  }
  if (below == 0)
    throw Error(p + "all " + std::to_string(s.Size()) + " SDF samples are >= the iso-value " + std::to_string(isovalue) +
                " (all outside): there is no surface to extract");
  if (above == 0)
    throw Error(p + "all " + std::to_string(s.Size()) + " SDF samples are < the iso-value " + std::to_string(isovalue) +
                " (all inside): there is no surface to extract");
}

}  // namespace arcs
