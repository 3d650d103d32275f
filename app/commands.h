// Subcommands implemented outside app/arcs.cpp (one file each). Each gets the
// whole argv (argv[1] is the command name) and returns the exit status; bad
// usage goes through cli::Usage (exit 2), errors throw (exit 1 in main).
#pragma once

#include "registry/registry.h"

namespace arcs {

int CmdVoxelize(Registry& registry, int argc, char** argv);  // app/cmd_voxelize.cpp
int CmdMorph(Registry& registry, int argc, char** argv);     // app/cmd_morph.cpp
int CmdPlot(int argc, char** argv);                          // app/cmd_plot.cpp (plot, render, report)

}  // namespace arcs
