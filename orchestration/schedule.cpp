#include "orchestration/schedule.h"

#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <thread>

namespace fs = std::filesystem;

namespace arcs {

namespace {

volatile std::sig_atomic_t g_interrupted = 0;
void OnSignal(int) { g_interrupted = 1; }

std::string Escape(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '\\') o += "\\\\";
    else if (c == '\n') o += "\\n";
    else if (c == '\t') o += "\\t";
    else o += c;
  }
  return o;
}

std::string Unescape(const std::string& s) {
  std::string o;
  for (size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '\\' && i + 1 < s.size()) {
      const char n = s[++i];
      o += n == 'n' ? '\n' : n == 't' ? '\t' : n;
    } else {
      o += s[i];
    }
  }
  return o;
}

void WriteRowFile(const std::string& path, const Row& row) {
  const std::string tmp = path + ".part";
  {
    std::ofstream out(tmp, std::ios::trunc);
    for (const auto& [k, v] : row) out << Escape(k) << '\t' << Escape(v) << '\n';
  }
  fs::rename(tmp, path);
}

bool ReadRowFile(const std::string& path, Row* row) {
  std::ifstream in(path);
  if (!in) return false;
  std::string line;
  while (std::getline(in, line)) {
    const size_t tab = line.find('\t');
    if (tab == std::string::npos) continue;
    row->emplace_back(Unescape(line.substr(0, tab)), Unescape(line.substr(tab + 1)));
  }
  return !row->empty();
}

}  // namespace

bool RunSchedule(const std::vector<const Case*>& todo, const ScheduleOptions& o, const ScheduleHooks& hooks) {
  g_interrupted = 0;
  struct sigaction sa {}, old_int {}, old_term {};
  sa.sa_handler = OnSignal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, &old_int);
  sigaction(SIGTERM, &sa, &old_term);

  if (!o.isolate) {
    for (const Case* c : todo) {
      if (g_interrupted) break;
      hooks.started(*c);
      hooks.finished(*c, hooks.execute(*c));
    }
  } else {
    std::map<pid_t, std::pair<const Case*, std::chrono::steady_clock::time_point>> running;
    size_t next = 0;
    while ((next < todo.size() || !running.empty()) && !g_interrupted) {
      while (next < todo.size() && static_cast<int>(running.size()) < std::max(1, o.jobs) && !g_interrupted) {
        const Case* c = todo[next++];
        std::fflush(nullptr);
        const pid_t parent = getpid();
        const pid_t pid = fork();
        if (pid < 0) {
          Row row = {{"case_id", c->id}, {"status", "failed"}, {"error", "fork failed: " + std::string(std::strerror(errno))}};
          hooks.finished(*c, row);
          continue;
        }
        if (pid == 0) {
          prctl(PR_SET_PDEATHSIG, SIGKILL);  // a worker does not outlive its runner (kill -9)
          if (getppid() != parent) _exit(1);
          // The worker ends here whatever happens: an exception must not
          // unwind into the parent's code path (it would run the loop on).
          int rc = 0;
          try {
            signal(SIGINT, SIG_DFL);
            signal(SIGTERM, SIG_DFL);
            Row row = hooks.execute(*c);
            WriteRowFile((fs::path(o.tmp_dir) / (c->id + ".row")).string(), row);
          } catch (const std::exception& e) {
            std::fprintf(stderr, "arcs: worker of case %s: %s\n", c->id.c_str(), e.what());
            rc = 3;
          } catch (...) {
            rc = 3;
          }
          std::fflush(nullptr);
          _exit(rc);
        }
        running[pid] = {c, std::chrono::steady_clock::now()};
        hooks.started(*c);
      }
      int status = 0;
      struct rusage ru {};
      const pid_t pid = wait4(-1, &status, WNOHANG, &ru);
      if (pid > 0 && running.count(pid)) {
        const Case* c = running[pid].first;
        running.erase(pid);
        const std::string row_file = (fs::path(o.tmp_dir) / (c->id + ".row")).string();
        Row row;
        if (WIFEXITED(status) && WEXITSTATUS(status) == 0 && ReadRowFile(row_file, &row)) {
          // The kernel's figure for the whole worker process.
          for (auto& [k, v] : row)
            if (k == "peak_rss_mb") v = std::to_string(ru.ru_maxrss / 1024.0);
        } else if (g_interrupted) {
          break;
        } else {
          std::string why = WIFSIGNALED(status) ? "worker crashed: signal " + std::to_string(WTERMSIG(status)) + " (" +
                                                      strsignal(WTERMSIG(status)) + ")"
                                                : "worker exited with status " + std::to_string(WEXITSTATUS(status));
          if (WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL && o.case_timeout_s > 0)
            why = "timed out after " + std::to_string(o.case_timeout_s) + " s (or killed: out of memory?)";
          row = {{"case_id", c->id}, {"status", "failed"}, {"error", why}, {"dataset", c->dataset}, {"item", c->item},
                 {"input", c->input}, {"method", c->method}, {"seed", std::to_string(c->seed)}};
          for (const auto& p : c->params) row.push_back(p);
          row.emplace_back("peak_rss_mb", std::to_string(ru.ru_maxrss / 1024.0));
        }
        std::error_code ec;
        fs::remove(row_file, ec);
        hooks.finished(*c, row);
        continue;
      }
      // Timeouts.
      if (o.case_timeout_s > 0) {
        for (auto& [p, info] : running) {
          const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - info.second).count();
          if (t > o.case_timeout_s) kill(p, SIGKILL);
        }
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    if (g_interrupted) {
      for (auto& [p, info] : running) kill(p, SIGTERM);
      for (auto& [p, info] : running) waitpid(p, nullptr, 0);
    }
  }
  sigaction(SIGINT, &old_int, nullptr);
  sigaction(SIGTERM, &old_term, nullptr);
  return g_interrupted != 0;
}

}  // namespace arcs
