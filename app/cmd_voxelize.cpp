// arcs voxelize (placeholder until the command lands).
#include "app/cli.h"
#include "app/commands.h"

namespace arcs {

int CmdVoxelize(Registry& registry, int argc, char** argv) {
  (void)registry;
  (void)argc;
  (void)argv;
  cli::Usage("voxelize: not available in this build yet");
}

}  // namespace arcs
