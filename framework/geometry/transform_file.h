// Transform sidecars of saved outputs. OUT.transform.json records the
// similarity that maps the input's frame to the frame OUT is written in
// (y = scale * rotation * (x + translation), Similarity's convention), e.g.
// the normalisation of `arcs sdf`, `arcs reconstruct --frame normalized` and
// the cases' outputs of `arcs run --save-outputs`:
//   {"maps": "...", "scale": s, "translation": [tx, ty, tz],
//    "rotation": [[r00, r01, r02], [...], [...]], "note": "..."}
#pragma once

#include "framework/geometry/normalize.h"

#include <string>

namespace arcs {

// Writes output + ".transform.json". Throws Error when it cannot be written.
void WriteTransformSidecar(const std::string& output, const Similarity& to_output_frame, const std::string& note);
// Reads output + ".transform.json" into *to_output_frame; false when there is
// none. A malformed sidecar is an InputError naming it.
bool ReadTransformSidecar(const std::string& output, Similarity* to_output_frame);

}  // namespace arcs
