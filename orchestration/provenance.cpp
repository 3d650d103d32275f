#include "orchestration/provenance.h"

#include "orchestration/version.h"
#include "registry/plugin.h"
#include "registry/plugin_api.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <thread>

namespace fs = std::filesystem;

namespace arcs {

namespace {
std::string Shell(const std::string& cmd) {
  std::string out;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return out;
  char buf[256];
  while (std::fgets(buf, sizeof buf, p)) out += buf;
  pclose(p);
  while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
  return out;
}

}  // namespace

std::string LocalTimeNow() {
  std::time_t t = std::time(nullptr);
  char buf[64];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%S%z", std::localtime(&t));
  return buf;
}

std::string Hostname() {
  char buf[256] = {0};
  gethostname(buf, sizeof buf - 1);
  return buf;
}

// The document after overrides, with every pipeline stage's parameters
// completed from the schema (swept ones keep their lists).
YAML::Node ResolvedConfig(const Experiment& exp, const Registry& registry) {
  YAML::Node doc = YAML::Clone(exp.resolved);
  auto fill = [&](YAML::Node pipelines, const std::vector<PipelineSpec>& specs) {
    for (size_t i = 0; i < specs.size() && i < pipelines.size(); ++i) {
      YAML::Node pl = pipelines[i]["pipeline"];
      for (size_t j = 0; j < specs[i].stages.size() && j < pl.size(); ++j) {
        const StageEntry& e = specs[i].stages[j];
        YAML::Node entry;
        entry["stage"] = e.stage;
        YAML::Node params(YAML::NodeType::Map);
        for (const auto& ps : registry.Get(e.stage).params.specs()) {
          auto it = std::find_if(e.values.begin(), e.values.end(), [&](const auto& kv) { return kv.first == ps.name; });
          if (it == e.values.end()) {
            params[ps.name] = FormatParamValue(ps.default_value);
          } else if (it->second.size() == 1) {
            params[ps.name] = FormatParamValue(it->second.front());
          } else {
            YAML::Node list(YAML::NodeType::Sequence);
            for (const auto& v : it->second) list.push_back(FormatParamValue(v));
            params[ps.name] = list;
          }
        }
        entry["params"] = params;
        pl[j] = entry;
      }
      pipelines[i]["name"] = specs[i].name;
    }
  };
  if (doc["inputs"]) fill(doc["inputs"], exp.inputs);
  if (doc["methods"]) fill(doc["methods"], exp.methods);
  doc["seed"] = exp.seed;
  doc["method_seed"] = exp.MethodSeedName();
  // Paths made absolute so `arcs table DIR` works from anywhere.
  // Built-in shapes and curves go back to `shapes` (a curves dataset's too,
  // so that the saved file runs again).
  for (size_t i = 0; i < exp.datasets.size() && doc["datasets"] && i < doc["datasets"].size(); ++i) {
    YAML::Node files(YAML::NodeType::Sequence), shapes(YAML::NodeType::Sequence);
    for (const auto& item : exp.datasets[i].items) {
      if (item.IsBuiltin()) shapes.push_back(item.name);
      else files.push_back(fs::absolute(item.path).lexically_normal().string());
    }
    YAML::Node d = doc["datasets"][i];
    d.remove("files");
    d.remove("shapes");
    if (files.size()) d["files"] = files;
    if (shapes.size()) d["shapes"] = shapes;
  }
  for (size_t i = 0; i < exp.tables.size() && doc["tables"] && i < doc["tables"].size(); ++i) {
    YAML::Node r = doc["tables"][i]["reference"];
    if (!r) continue;
    const auto& refs = exp.tables[i].references;
    if (r.IsSequence()) {
      for (size_t k = 0; k < r.size() && k < refs.size(); ++k) r[k]["file"] = fs::absolute(refs[k].file).string();
    } else if (!refs.empty()) {
      r["file"] = fs::absolute(refs[0].file).string();
    }
  }
  return doc;
}

std::string ProvenanceText(const Experiment& exp, const RunOptions& o, int threads, const CpuAllocation& cpu,
                           const std::string& experiment_id) {
  YAML::Emitter e;
  e << YAML::BeginMap;
  e << YAML::Key << "arcs_version" << YAML::Value << "0.1.0";
  e << YAML::Key << "plugin_api_version" << YAML::Value << ARCS_PLUGIN_API_VERSION;
  e << YAML::Key << "git_revision_at_build" << YAML::Value << GitRevision();
  const std::string rev = Shell(std::string("git -C '") + SourceDir() + "' rev-parse HEAD 2>/dev/null");
  const std::string dirty = Shell(std::string("git -C '") + SourceDir() + "' status --porcelain 2>/dev/null | head -1");
  e << YAML::Key << "git_revision_now" << YAML::Value << (rev.empty() ? "unknown" : rev);
  e << YAML::Key << "git_dirty" << YAML::Value << !dirty.empty();
  e << YAML::Key << "build_type" << YAML::Value << BuildType();
  e << YAML::Key << "host" << YAML::Value << Hostname();
  e << YAML::Key << "cores" << YAML::Value << std::thread::hardware_concurrency();
  e << YAML::Key << "cpus" << YAML::Value << cpu.cpus;
  e << YAML::Key << "cpus_from" << YAML::Value << cpu.source;
  e << YAML::Key << "affinity_cpus" << YAML::Value << cpu.affinity_cpus;
  if (cpu.slurm_cpus > 0) e << YAML::Key << "slurm_cpus_per_task" << YAML::Value << cpu.slurm_cpus;
  for (const char* v : {"SLURM_JOB_ID", "SLURM_ARRAY_JOB_ID", "SLURM_ARRAY_TASK_ID", "SLURM_JOB_PARTITION"})
    if (const char* x = std::getenv(v)) e << YAML::Key << v << YAML::Value << x;
  e << YAML::Key << "pid" << YAML::Value << static_cast<long>(getpid());
  e << YAML::Key << "started" << YAML::Value << LocalTimeNow();
  e << YAML::Key << "experiment_id" << YAML::Value << experiment_id;
  e << YAML::Key << "shard" << YAML::Value << o.shard.Text();
  e << YAML::Key << "shard_from" << YAML::Value << (o.shard.source.empty() ? "none" : o.shard.source);
  e << YAML::Key << "experiment" << YAML::Value << fs::absolute(exp.file).string();
  e << YAML::Key << "seed" << YAML::Value << exp.seed;
  e << YAML::Key << "method_seed" << YAML::Value << exp.MethodSeedName();
  e << YAML::Key << "jobs" << YAML::Value << o.jobs;
  e << YAML::Key << "threads_per_case" << YAML::Value << threads;
  e << YAML::Key << "isolated_processes" << YAML::Value << o.isolate;
  std::string cmd;
  for (const auto& a : o.command_line) cmd += (cmd.empty() ? "" : " ") + a;
  e << YAML::Key << "command" << YAML::Value << cmd;
  e << YAML::Key << "plugins" << YAML::Value << YAML::BeginSeq;
  for (const auto& p : LoadedPlugins()) {
    e << YAML::BeginMap << YAML::Key << "path" << YAML::Value << p.path << YAML::Key << "name" << YAML::Value
      << p.name << YAML::Key << "version" << YAML::Value << p.version << YAML::Key << "stages" << YAML::Value
      << YAML::Flow << p.stages << YAML::EndMap;
  }
  e << YAML::EndSeq << YAML::EndMap;
  return std::string(e.c_str()) + "\n";
}

}  // namespace arcs
