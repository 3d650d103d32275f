// The 2D slots of a case the 2D stages read: CaseData::reference_curve and
// CaseData::output_curve, with the errors that say what is missing.
#pragma once

#include "framework/error.h"
#include "registry/stage.h"

#include <string>

namespace arcs {

inline const Polyline& RequireReferenceCurve(const CaseData& d, const std::string& stage) {
  if (!d.reference_curve)
    throw Error(stage + ": needs a 2D reference curve (a dataset of kind 'curves'); this case has " +
                (d.reference ? "a 3D reference mesh" : "no reference"));
  return *d.reference_curve;
}

inline const Polyline& RequireOutputCurve(const CaseData& d, const std::string& stage) {
  if (!d.output_curve)
    throw Error(stage + ": needs a 2D output curve (from marching_squares, screened_poisson_2d or rfta on 2D samples)" +
                (d.output ? std::string("; this case's output is a 3D mesh") : std::string()));
  return *d.output_curve;
}

}  // namespace arcs
