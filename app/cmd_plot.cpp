// arcs plot | render | report: figures, mesh renders and an HTML report of a
// results directory. The drawing is Python (scripts/arcs_plot.py, Debian's
// python3-matplotlib, headless Agg); this command finds the script and an
// interpreter that has matplotlib and hands it the arguments.
//   script: $ARCS_PLOT_SCRIPT, else <prefix>/share/arcs/arcs_plot.py beside an
//           installed binary, else the source tree's scripts/arcs_plot.py;
//   python: $ARCS_PYTHON, else /usr/bin/python3 (where Debian's matplotlib
//           lives, even when another python3 comes first in PATH), else python3.
#include "app/commands.h"
#include "framework/error.h"

#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#ifndef ARCS_SOURCE_SCRIPTS_DIR
#define ARCS_SOURCE_SCRIPTS_DIR ""
#endif

namespace arcs {

namespace {

namespace fs = std::filesystem;

std::string FindPlotScript() {
  if (const char* s = std::getenv("ARCS_PLOT_SCRIPT")) {
    if (!fs::exists(s)) throw Error(std::string("ARCS_PLOT_SCRIPT=") + s + ": no such file");
    return s;
  }
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  std::vector<fs::path> candidates;
  if (!ec) candidates.push_back(exe.parent_path().parent_path() / "share" / "arcs" / "arcs_plot.py");
  candidates.push_back(fs::path(ARCS_SOURCE_SCRIPTS_DIR) / "arcs_plot.py");
  for (const auto& c : candidates)
    if (fs::exists(c)) return c.string();
  std::string tried;
  for (const auto& c : candidates) tried += " " + c.string();
  throw Error("arcs_plot.py not found (tried" + tried + "; set ARCS_PLOT_SCRIPT)");
}

std::string FindPython() {
  if (const char* p = std::getenv("ARCS_PYTHON")) return p;
  if (access("/usr/bin/python3", X_OK) == 0) return "/usr/bin/python3";
  return "python3";
}

}  // namespace

int CmdPlot(int argc, char** argv) {
  const std::string script = FindPlotScript();
  const std::string python = FindPython();
  std::vector<char*> cargs;
  cargs.push_back(const_cast<char*>(python.c_str()));
  cargs.push_back(const_cast<char*>(script.c_str()));
  for (int i = 1; i < argc; ++i) cargs.push_back(argv[i]);  // argv[1] = plot | render | report
  cargs.push_back(nullptr);
  execvp(python.c_str(), cargs.data());
  throw Error("cannot run " + python + " for arcs " + argv[1] + ": " + std::strerror(errno) +
              " (install python3-matplotlib: scripts/install_deps.sh)");
}

}  // namespace arcs
