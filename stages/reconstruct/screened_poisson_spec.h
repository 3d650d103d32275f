// The `screened_poisson` stage configured as the official Reach for the
// Arcs calls PoissonRecon (framework/reconstruct/poisson.h,
// OfficialRftaPoisson: `rfta`'s final surface) and as RFTA's fine-tuning
// surfaces are made (RftaTuningPoisson: `rfta`'s tuning_reconstructor and
// `fine_tune`'s reconstructor).
#pragma once

#include "framework/reconstruct/poisson.h"
#include "registry/param.h"

#include <cstdint>
#include <string>

namespace arcs {

// The `screened_poisson` stage set to PoissonOptions o's values (the
// arcs back-end's settings that an RFTA preset fixes).
inline StageSpec PoissonSpecOf(const PoissonOptions& o) {
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
  s.params.Set("normal_splat", EnumToName(kSpsrNormalSplatNames, o.normal_splat));
  s.params.Set("density_scale", o.density_scale);
  return s;
}

// The official call in full: RFTA's final surface.
inline StageSpec OfficialPoissonSpec() { return PoissonSpecOf(OfficialRftaPoisson()); }

// RFTA's fine-tuning surfaces (RftaTuningPoisson).
inline StageSpec RftaTuningPoissonSpec() { return PoissonSpecOf(RftaTuningPoisson()); }

}  // namespace arcs
