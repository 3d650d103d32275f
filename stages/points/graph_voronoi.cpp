// graph_voronoi stages (placeholder until the stages land).
#include "stages/builtin.h"

namespace arcs {

void RegisterGraphVoronoi(Registry& r) { (void)r; }

}  // namespace arcs
