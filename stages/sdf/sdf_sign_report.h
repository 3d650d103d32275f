// The per-case report of how sdf_grid / sdf_random decided the SDF's sign
// (framework/sdf/sdf_sampling.h, SdfSignReport) as result columns.
#pragma once

#include "framework/sdf/sdf_sampling.h"
#include "registry/stage.h"

namespace arcs {

// sdf_unbalanced_edges: 0 = closed and consistently oriented (the rule is the
// paper's sign there); sdf_shell_samples: samples inside only by the open-mesh
// shell; sdf_inward: 1 when the mesh faces inward (negative volume);
// sdf_inside_samples: samples with s < 0. The warnings went to the log.
inline void ReportSdfSign(const SdfSignReport& rep, CaseData& d) {
  d.SetMetric("sdf_unbalanced_edges", static_cast<double>(rep.unbalanced_edges));
  d.SetMetric("sdf_shell_samples", static_cast<double>(rep.shell_samples));
  d.SetMetric("sdf_inward", rep.signed_volume < 0.0 ? 1.0 : 0.0);
  d.SetMetric("sdf_inside_samples", static_cast<double>(rep.inside));
}

}  // namespace arcs
