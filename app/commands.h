// Subcommands implemented outside app/arcs.cpp (one file each). Each gets the
// whole argv (argv[1] is the command name) and returns the exit status; bad
// usage goes through cli::Usage (exit 2), errors throw (exit 1 in main).
#pragma once

#include "registry/registry.h"

#include <string>
#include <vector>

namespace arcs {

int CmdVoxelize(Registry& registry, int argc, char** argv);  // app/cmd_voxelize.cpp
int CmdMorph(Registry& registry, int argc, char** argv);     // app/cmd_morph.cpp
int CmdSlurm(Registry& registry, int argc, char** argv);     // app/cmd_slurm.cpp
int CmdEval(int argc, char** argv);                           // app/cmd_eval.cpp
// `arcs reconstruct` on a point cloud (a reconstructor stage); app/cmd_reconstruct_points.cpp.
int CmdReconstructPoints(Registry& registry, int argc, char** argv);
// True when `arcs reconstruct INPUT ... [--method M]` is a point-cloud reconstruction:
// M is a reconstructor, or no --method and INPUT is a point-cloud file (.ply .xyz .pwn .pcd).
bool IsPointReconstruction(const Registry& registry, const std::string& input, const std::string& method);

// Options valid anywhere on the command line (app/cmd_help.cpp).
struct GlobalOptions {
  std::vector<std::string> plugins;  // --plugin FILE (repeatable)
  int threads = 0;                   // --threads T
  bool has_threads = false;
  bool version = false;              // --version (before the command)
  bool help = false;                 // --help / -h after the command
};
// Removes --plugin, --threads and a leading --version from argv (keeps --help),
// wherever they are, and returns them.
GlobalOptions ExtractGlobalOptions(int* argc, char** argv);
// Prints `arcs CMD --help` (generated from the stage schemas where a stage is
// behind the command); false when CMD has no entry (it prints its own).
bool PrintCommandHelp(const Registry& registry, const std::string& cmd, int argc, char** argv);

int CmdPlot(int argc, char** argv);                          // app/cmd_plot.cpp (plot, render, report)

}  // namespace arcs
