#include "orchestration/results_dir.h"

#include "framework/error.h"
#include "framework/util/rng.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace fs = std::filesystem;

namespace arcs {

namespace {

bool ParseNonNegative(const std::string& s, long* out) {
  if (s.empty() || s.size() > 9) return false;
  for (char c : s)
    if (c < '0' || c > '9') return false;
  *out = std::strtol(s.c_str(), nullptr, 10);
  return true;
}

std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string HostName() {
  char buf[256] = {0};
  gethostname(buf, sizeof buf - 1);
  return buf;
}

std::string NowText() {
  std::time_t t = std::time(nullptr);
  char buf[64];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%S%z", std::localtime(&t));
  return buf;
}

// Writes a file atomically (temp file in the same directory + rename).
void WriteAtomically(const fs::path& path, const std::string& text) {
  const fs::path tmp = path.string() + ".tmp." + std::to_string(getpid());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << text;
    out.flush();
    if (!out) throw Error("cannot write " + tmp.string());
  }
  fs::rename(tmp, path);
}

// experiment.id: "key: value" lines.
std::map<std::string, std::string> ReadIdFile(const fs::path& path) {
  std::map<std::string, std::string> kv;
  std::istringstream in(ReadText(path.string()));
  std::string line;
  while (std::getline(in, line)) {
    const size_t c = line.find(": ");
    if (c != std::string::npos) kv[line.substr(0, c)] = line.substr(c + 2);
  }
  return kv;
}

}  // namespace

Shard ParseShard(const std::string& text, const std::string& what) {
  const size_t slash = text.find('/');
  long i = -1, n = -1;
  if (slash == std::string::npos || !ParseNonNegative(text.substr(0, slash), &i) ||
      !ParseNonNegative(text.substr(slash + 1), &n) || n < 1 || i >= n)
    throw Error(what + " '" + text + "': expected I/N with 0 <= I < N (e.g. 0/3, 1/3, 2/3)");
  Shard s;
  s.index = static_cast<int>(i);
  s.count = static_cast<int>(n);
  s.source = what;
  return s;
}

Shard ShardFromEnvironment() {
  const char* id = std::getenv("SLURM_ARRAY_TASK_ID");
  if (!id) return Shard{};
  auto get = [](const char* name, long def) {
    const char* v = std::getenv(name);
    long x = def;
    if (v && !ParseNonNegative(v, &x))
      throw Error(std::string("$") + name + " = '" + v + "' is not a non-negative integer");
    return x;
  };
  const long task = get("SLURM_ARRAY_TASK_ID", 0);
  const long count = get("SLURM_ARRAY_TASK_COUNT", -1);
  const long min = get("SLURM_ARRAY_TASK_MIN", 0);
  const long step = std::max(1L, get("SLURM_ARRAY_TASK_STEP", 1));
  if (count < 1)
    throw Error("$SLURM_ARRAY_TASK_ID is set but $SLURM_ARRAY_TASK_COUNT is not: give --shard I/N explicitly");
  const long index = (task - min) / step;
  if (task < min || index >= count)
    throw Error("$SLURM_ARRAY_TASK_ID " + std::to_string(task) + " does not fit an array of " + std::to_string(count) +
                " tasks from " + std::to_string(min) + ": give --shard I/N explicitly");
  Shard s;
  s.index = static_cast<int>(index);
  s.count = static_cast<int>(count);
  s.source = "SLURM_ARRAY_TASK_ID";
  return s;
}

std::vector<const Case*> ShardCases(const std::vector<Case>& cases, const Shard& shard) {
  std::vector<const Case*> out;
  if (shard.count <= 1) {
    for (const auto& c : cases) out.push_back(&c);
    return out;
  }
  // Cost rank: product of the numeric swept values, larger first, ties by id.
  std::vector<std::pair<double, size_t>> rank(cases.size());
  for (size_t i = 0; i < cases.size(); ++i) {
    double cost = 1;
    for (const auto& [k, v] : cases[i].params) {
      if (std::find(cases[i].varying.begin(), cases[i].varying.end(), k) == cases[i].varying.end()) continue;
      char* end = nullptr;
      const double x = std::strtod(v.c_str(), &end);
      if (!v.empty() && !*end && std::isfinite(x)) cost *= std::max(1.0, std::fabs(x));
    }
    rank[i] = {cost, i};
  }
  std::sort(rank.begin(), rank.end(), [&](const auto& a, const auto& b) {
    if (a.first != b.first) return a.first > b.first;
    return cases[a.second].id < cases[b.second].id;
  });
  std::vector<char> mine(cases.size(), 0);
  for (size_t k = 0; k < rank.size(); ++k)
    if (static_cast<int>(k % shard.count) == shard.index) mine[rank[k].second] = 1;
  for (size_t i = 0; i < cases.size(); ++i)
    if (mine[i]) out.push_back(&cases[i]);
  return out;
}

std::string ResultsFileName(const Shard& shard) {
  if (!shard.sharded()) return "results.csv";
  return "results." + std::to_string(shard.index) + "-of-" + std::to_string(shard.count) + ".csv";
}

std::vector<std::string> ResultsFiles(const std::string& dir) {
  std::vector<std::string> files;
  if (fs::exists(fs::path(dir) / "results.csv")) files.push_back((fs::path(dir) / "results.csv").string());
  std::vector<std::string> shards;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string n = e.path().filename().string();
    const size_t of = n.find("-of-");
    if (n.rfind("results.", 0) != 0 || n.size() < 4 || n.compare(n.size() - 4, 4, ".csv") != 0 ||
        of == std::string::npos || !e.is_regular_file())
      continue;
    long i, c;
    if (ParseNonNegative(n.substr(8, of - 8), &i) && ParseNonNegative(n.substr(of + 4, n.size() - 4 - of - 4), &c))
      shards.push_back(e.path().string());
  }
  std::sort(shards.begin(), shards.end());
  files.insert(files.end(), shards.begin(), shards.end());
  return files;
}

size_t CompleteCsvPrefix(const std::string& text) {
  bool quoted = false;
  size_t line_start = 0, fields = 1, last_start = 0, last_end = 0;
  long header_fields = -1;
  bool last_ok = true;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '"') {
      quoted = !quoted;
    } else if (quoted) {
      continue;
    } else if (c == ',') {
      ++fields;
    } else if (c == '\n') {
      const char first = text[line_start];
      const bool skip = first == '#' || first == '\n' || first == '\r';
      bool ok = true;
      if (!skip) {
        if (header_fields < 0) header_fields = static_cast<long>(fields);
        else ok = static_cast<long>(fields) == header_fields;
      }
      last_start = line_start, last_end = i + 1, last_ok = ok;
      line_start = i + 1;
      fields = 1;
    }
  }
  // A last line that ends but has the wrong number of fields is torn too.
  return last_ok ? last_end : last_start;
}

std::uintmax_t RepairTornTail(const std::string& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) return 0;
  const std::string text = ReadText(path);
  const size_t keep = CompleteCsvPrefix(text);
  if (keep == text.size()) return 0;
  fs::resize_file(path, keep);
  return text.size() - keep;
}

namespace {

// Appends the rows of results files to `all`, deduplicated by case id.
void MergeResultsFiles(const std::vector<std::string>& files, CsvTable& all, std::map<std::string, size_t>& by_id,
                       std::vector<std::string>* warnings) {
  for (const auto& f : files) {
    std::string text = ReadText(f);
    const size_t keep = CompleteCsvPrefix(text);
    if (keep < text.size()) {
      if (warnings)
        warnings->push_back(f + ": its last " + std::to_string(text.size() - keep) +
                            " bytes are not a complete row (being written, or torn); left out");
      text.resize(keep);
    }
    const CsvTable t = ParseCsv(text, f);
    std::vector<int> to(t.header.size());
    for (size_t c = 0; c < t.header.size(); ++c) {
      int k = all.Column(t.header[c]);
      if (k < 0) {
        all.header.push_back(t.header[c]);
        for (auto& r : all.rows) r.emplace_back();
        k = static_cast<int>(all.header.size()) - 1;
      }
      to[c] = k;
    }
    const int id_col = t.Column("case_id"), st_col = t.Column("status");
    for (const auto& r : t.rows) {
      std::vector<std::string> row(all.header.size());
      for (size_t c = 0; c < r.size(); ++c) row[to[c]] = r[c];
      const std::string id = id_col >= 0 ? r[id_col] : "";
      const auto it = id.empty() ? by_id.end() : by_id.find(id);
      if (it == by_id.end()) {
        if (!id.empty()) by_id[id] = all.rows.size();
        all.rows.push_back(std::move(row));
        continue;
      }
      // Seen before: an ok row replaces a failed one; the later of two alike wins.
      const int st_all = all.Column("status");
      const bool old_ok = st_all >= 0 && all.rows[it->second][st_all] == "ok";
      const bool new_ok = st_col >= 0 && r[st_col] == "ok";
      if (new_ok || !old_ok) all.rows[it->second] = std::move(row);
    }
  }
}

}  // namespace

CsvTable ReadResultsDir(const std::string& dir, std::vector<std::string>* warnings) {
  const std::vector<std::string> files = ResultsFiles(dir);
  if (files.empty())
    throw Error((fs::path(dir) / "results.csv").string() + ": no results file (run the experiment first)");
  CsvTable all;
  std::map<std::string, size_t> by_id;  // case id -> row in `all`
  MergeResultsFiles(files, all, by_id, warnings);
  if (warnings) {
    const fs::path idf = fs::path(dir) / "experiment.id";
    if (fs::exists(idf)) {
      const auto kv = ReadIdFile(idf);
      long expected = -1;
      if (kv.count("cases") && ParseNonNegative(kv.at("cases"), &expected) &&
          static_cast<long>(by_id.size()) < expected)
        warnings->push_back(dir + ": " + std::to_string(by_id.size()) + " of " + std::to_string(expected) +
                            " cases have results (" + std::to_string(expected - static_cast<long>(by_id.size())) +
                            " missing: a shard not run, still running, or interrupted?)");
    }
  }
  return all;
}

CsvTable ReadResults(const std::vector<std::string>& sources, std::vector<std::string>* warnings) {
  if (sources.empty()) throw Error("no results given (a results directory or a results .csv file)");
  CsvTable all;
  std::map<std::string, size_t> by_id;
  for (const std::string& src : sources) {
    std::error_code ec;
    if (fs::is_directory(src, ec)) {
      const std::vector<std::string> files = ResultsFiles(src);
      if (files.empty())
        throw Error((fs::path(src) / "results.csv").string() + ": no results file (run the experiment first)");
      MergeResultsFiles(files, all, by_id, warnings);
    } else if (fs::is_regular_file(src, ec)) {
      MergeResultsFiles({src}, all, by_id, warnings);
    } else {
      throw Error(src + ": no such results directory or file");
    }
  }
  return all;
}

FileLock::~FileLock() { Unlock(); }

void FileLock::Unlock() {
  if (fd_ >= 0) ::close(fd_);  // closing the last descriptor releases the flock
  fd_ = -1;
}

bool FileLock::TryLock(const std::string& path, const std::string& what, std::string* holder) {
  Unlock();
  const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) throw Error(path + ": cannot open lock file: " + std::strerror(errno));
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    const int err = errno;
    ::close(fd);
    if (err != EWOULDBLOCK) throw Error(path + ": cannot lock: " + std::strerror(err));
    if (holder) {
      *holder = ReadText(path);
      while (!holder->empty() && holder->back() == '\n') holder->pop_back();
      if (holder->empty()) *holder = "another process";
    }
    return false;
  }
  fd_ = fd;
  const std::string who =
      "pid " + std::to_string(getpid()) + " on host " + HostName() + " since " + NowText() + ": " + what + "\n";
  if (::ftruncate(fd_, 0) == 0) (void)!::pwrite(fd_, who.data(), who.size(), 0);
  return true;
}

void FileLock::Lock(const std::string& path) {
  Unlock();
  const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) throw Error(path + ": cannot open lock file: " + std::strerror(errno));
  while (::flock(fd, LOCK_EX) != 0) {
    if (errno == EINTR) continue;
    const int err = errno;
    ::close(fd);
    throw Error(path + ": cannot lock: " + std::strerror(err));
  }
  fd_ = fd;
}

std::string ExperimentIdentity(const std::vector<Case>& cases) {
  std::vector<std::string> ids;
  for (const auto& c : cases) ids.push_back(c.id);
  std::sort(ids.begin(), ids.end());
  std::string key;
  for (const auto& id : ids) key += id + "\n";
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(Fnv1a64(key)));
  return buf;
}

void CheckResultsDir(const std::string& dir, const Experiment& exp, const std::vector<Case>& cases) {
  const fs::path d(dir);
  if (!fs::exists(d)) return;
  const std::string id = ExperimentIdentity(cases);
  const fs::path idf = d / "experiment.id";
  if (fs::exists(idf)) {
    const auto kv = ReadIdFile(idf);
    const std::string theirs = kv.count("id") ? kv.at("id") : "";
    if (theirs != id)
      throw Error(dir + " holds the results of another experiment ('" + (kv.count("name") ? kv.at("name") : "?") +
                  "', id " + theirs + ", " + (kv.count("cases") ? kv.at("cases") : "?") + " cases); this one is '" +
                  exp.name + "' (id " + id + ", " + std::to_string(cases.size()) +
                  " cases): other items, parameters, metrics or seed. Use another --out (or remove " + dir + ")");
  } else {
    // A directory from before experiment.id: its rows must be cases of ours.
    if (!ResultsFiles(dir).empty()) {
      std::set<std::string> ours;
      for (const auto& c : cases) ours.insert(c.id);
      const CsvTable t = ReadResultsDir(dir);
      const int col = t.Column("case_id");
      size_t foreign = 0;
      std::string example;
      for (size_t r = 0; col >= 0 && r < t.rows.size(); ++r)
        if (!ours.count(t.rows[r][col]) && !foreign++) example = t.rows[r][col];
      if (foreign > 0)
        throw Error(dir + " holds " + std::to_string(foreign) + " result rows of cases that experiment '" + exp.name +
                    "' does not have (e.g. case " + example +
                    "): results of another experiment. Use another --out (or remove " + dir + ")");
    }
  }
}

void ClaimResultsDir(const std::string& dir, const Experiment& exp, const std::vector<Case>& cases,
                     const std::string& resolved_config, const std::string& provenance) {
  const fs::path d(dir);
  fs::create_directories(d / "locks");
  FileLock lock;
  lock.Lock((d / "locks" / "dir.lock").string());
  CheckResultsDir(dir, exp, cases);
  const std::string id = ExperimentIdentity(cases);
  const fs::path idf = d / "experiment.id";
  if (!fs::exists(idf)) {
    WriteAtomically(idf, "id: " + id + "\nname: " + exp.name + "\ncases: " + std::to_string(cases.size()) +
                             "\nexperiment: " + fs::absolute(exp.file).string() + "\n");
  }
  const fs::path cfg = d / "config.resolved.yaml";
  if (!fs::exists(cfg) || ReadText(cfg.string()) != resolved_config) WriteAtomically(cfg, resolved_config);
  // Provenance: one document per run, appended in one write.
  const std::string doc = "---\n" + provenance + (provenance.empty() || provenance.back() == '\n' ? "" : "\n");
  const int fd = ::open((d / "provenance.yaml").c_str(), O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) throw Error((d / "provenance.yaml").string() + ": cannot append: " + std::strerror(errno));
  const ssize_t w = ::write(fd, doc.data(), doc.size());
  ::fsync(fd);
  ::close(fd);
  if (w != static_cast<ssize_t>(doc.size())) throw Error((d / "provenance.yaml").string() + ": short write");
}

}  // namespace arcs
