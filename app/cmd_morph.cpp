// arcs morph (placeholder until the command lands).
#include "app/cli.h"
#include "app/commands.h"

namespace arcs {

int CmdMorph(Registry& registry, int argc, char** argv) {
  (void)registry;
  (void)argc;
  (void)argv;
  cli::Usage("morph: not available in this build yet");
}

}  // namespace arcs
