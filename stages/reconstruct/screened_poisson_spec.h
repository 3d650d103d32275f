// The `screened_poisson` stage configured as the official Reach for the
// Arcs calls PoissonRecon (framework/reconstruct/poisson.h,
// OfficialRftaPoisson): the default reconstructors of `rfta` and `fine_tune`.
#pragma once

#include "framework/reconstruct/poisson.h"
#include "registry/param.h"

#include <cstdint>
#include <string>

namespace arcs {

inline StageSpec OfficialPoissonSpec() {
  const PoissonOptions o = OfficialRftaPoisson();
  StageSpec s;
  s.stage = "screened_poisson";
  s.params.Set("backend", std::string("arcs"));
  s.params.Set("depth", std::int64_t{o.depth});
  s.params.Set("scale", o.scale);
  s.params.Set("samples_per_node", o.samples_per_node);
  s.params.Set("point_weight", o.point_weight);
  s.params.Set("open_retries", std::int64_t{o.open_retries});
  s.params.Set("area_normalized", o.area_normalized);
  s.params.Set("fine_solver", EnumToName(kSpsrFineSolverNames, o.fine_solver));
  return s;
}

}  // namespace arcs
