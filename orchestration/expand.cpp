#include "orchestration/expand.h"

#include "framework/util/rng.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <set>

namespace arcs {

std::string Case::Label() const {
  std::string s = item;
  for (const auto& [k, v] : params) {
    if (std::find(varying.begin(), varying.end(), k) == varying.end()) continue;
    const auto it = std::find_if(shown.begin(), shown.end(), [&](const auto& e) { return e.first == k; });
    s += " " + k.substr(k.rfind('.') + 1) + "=" + (it != shown.end() ? it->second : v);
  }
  return s + " | " + input + " | " + method;
}

namespace {

// Cartesian product of a pipeline's sweeps, each resolved against the registry.
std::vector<std::vector<StageSpec>> ExpandPipeline(const PipelineSpec& p, const Registry& registry) {
  std::vector<std::vector<StageSpec>> out(1);
  for (const auto& entry : p.stages) {
    // A value swept twice would run the same case twice under one id: refused.
    for (const auto& [key, values] : entry.values) {
      std::map<std::string, size_t> seen;
      for (size_t i = 0; i < values.size(); ++i) {
        const std::string v = FormatParamValue(values[i]);
        if (!seen.emplace(v, i).second)
          throw ExperimentError(entry.where + ": " + p.name + "." + entry.stage + ".params." + key + ": sweep value " +
                                v + " is listed twice (at [" + std::to_string(seen[v]) + "] and [" + std::to_string(i) +
                                "]); each value runs once, remove the repeat");
      }
    }
    // Product over this entry's parameters.
    std::vector<ParamMap> variants(1);
    for (const auto& [key, values] : entry.values) {
      std::vector<ParamMap> next;
      for (const auto& base : variants)
        for (const auto& v : values) {
          ParamMap m = base;
          m.Set(key, v);
          next.push_back(std::move(m));
        }
      variants = std::move(next);
    }
    std::vector<std::vector<StageSpec>> next;
    for (const auto& prefix : out)
      for (const auto& given : variants) {
        auto seq = prefix;
        ParamMap resolved;
        try {
          resolved = registry.Resolve(entry.stage, given);
        } catch (const Error& e) {
          throw ExperimentError(entry.where + ": " + e.what());
        }
        seq.push_back(StageSpec{entry.stage, resolved});
        next.push_back(std::move(seq));
      }
    out = std::move(next);
  }
  return out;
}

void AddParamColumns(const std::vector<StageSpec>& stages,
                     std::vector<std::pair<std::string, std::string>>* cols) {
  std::map<std::string, int> seen;
  for (const auto& s : stages) {
    const int k = seen[s.stage]++;
    const std::string prefix = k == 0 ? s.stage : s.stage + "#" + std::to_string(k + 1);
    for (const auto& [name, v] : s.params.items()) cols->emplace_back(prefix + "." + name, FormatParamValue(v));
  }
}

std::string Hex16(std::uint64_t x) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(x));
  return buf;
}

std::uint64_t MaxCases() {
  if (const char* v = std::getenv("ARCS_MAX_CASES")) {
    char* end = nullptr;
    const unsigned long long x = std::strtoull(v, &end, 10);
    if (*v && !*end && x > 0) return x;
    throw ExperimentError(std::string("$ARCS_MAX_CASES = '") + v + "' is not a positive integer");
  }
  return 100000;
}

// Counts the cases first (saturating), so a huge sweep is an error, not an
// out-of-memory.
void CheckCaseCount(const Experiment& exp) {
  const std::uint64_t cap = MaxCases(), big = std::uint64_t(1) << 62;
  auto mul = [&](std::uint64_t a, std::uint64_t b) { return a == 0 || b <= big / a ? a * b : big; };
  auto variants = [&](const PipelineSpec& p) {
    std::uint64_t n = 1;
    for (const auto& e : p.stages)
      for (const auto& kv : e.values) n = mul(n, kv.second.size());
    return n;
  };
  std::uint64_t items = 0, ins = exp.inputs.empty() ? 1 : 0, ms = 0;
  for (const auto& ds : exp.datasets) items = std::min(big, items + ds.items.size());
  for (const auto& in : exp.inputs) ins = std::min(big, ins + variants(in));
  for (const auto& m : exp.methods) ms = std::min(big, ms + variants(m));
  const std::uint64_t total = mul(mul(items, ins), ms);
  if (total > cap)
    throw ExperimentError(exp.file + ": the experiment expands to " + (total >= big ? "more than 4e18" : std::to_string(total)) +
                          " cases (" + std::to_string(items) + " items x " + std::to_string(ins) + " input variants x " +
                          std::to_string(ms) + " method variants), more than the limit of " + std::to_string(cap) +
                          "; sweep fewer values, or raise the limit with ARCS_MAX_CASES");
}

// A nested stage's value as FormatParamValue writes it, "stage(k=v, k=v)",
// split into the stage and its (key, value) pairs at the top level (values
// may hold nested stages or lists); false for any other value.
bool SplitNestedValue(const std::string& v, std::string* stage, std::vector<std::pair<std::string, std::string>>* kv) {
  const std::size_t open = v.find('(');
  if (open == std::string::npos || open == 0 || v.back() != ')') return false;
  for (std::size_t i = 0; i < open; ++i)
    if (!(std::isalnum(static_cast<unsigned char>(v[i])) || v[i] == '_' || v[i] == '.' || v[i] == '-')) return false;
  *stage = v.substr(0, open);
  kv->clear();
  const std::string body = v.substr(open + 1, v.size() - open - 2);
  int depth = 0;
  std::size_t start = 0;
  for (std::size_t i = 0; i <= body.size(); ++i) {
    const bool end = i == body.size();
    if (end || (depth == 0 && body.compare(i, 2, ", ") == 0)) {
      const std::string part = body.substr(start, i - start);
      if (!part.empty()) {
        const std::size_t eq = part.find('=');
        if (eq == std::string::npos || eq == 0) return false;
        kv->emplace_back(part.substr(0, eq), part.substr(eq + 1));
      }
      if (end) break;
      start = i + 2;
      ++i;
      continue;
    }
    if (body[i] == '(' || body[i] == '[') ++depth;
    else if (body[i] == ')' || body[i] == ']') --depth;
  }
  return depth == 0;
}

// Marks the parameter columns that vary across the cases (progress labels),
// and for a varying nested stage the short form its labels show: the stage
// with only its nested parameters that vary (the whole resolved call of
// screened_poisson is some 300 characters).
void MarkVarying(std::vector<Case>* cases) {
  std::map<std::string, std::set<std::string>> values;
  for (const auto& c : *cases)
    for (const auto& [k, v] : c.params) values[k].insert(v);
  std::vector<std::string> varying;
  for (const auto& [k, vs] : values)
    if (vs.size() > 1) varying.push_back(k);
  for (auto& c : *cases) c.varying = varying;
  for (const std::string& k : varying) {
    // Each case's split value of column k; a column any case does not split
    // is shown whole.
    std::vector<std::pair<std::string, std::vector<std::pair<std::string, std::string>>>> split(cases->size());
    bool nested = true;
    for (std::size_t i = 0; i < cases->size() && nested; ++i) {
      const auto& ps = (*cases)[i].params;
      const auto it = std::find_if(ps.begin(), ps.end(), [&](const auto& e) { return e.first == k; });
      nested = it != ps.end() && SplitNestedValue(it->second, &split[i].first, &split[i].second);
    }
    if (!nested) continue;
    // Per nested stage, the keys whose values vary among the cases of that
    // stage (a key missing from some of them counts as varying); another
    // stage is told apart by its name.
    std::map<std::string, std::map<std::string, std::set<std::string>>> seen;
    std::map<std::string, std::map<std::string, std::size_t>> has;
    std::map<std::string, std::size_t> count;
    for (const auto& [stage, kv] : split) {
      ++count[stage];
      for (const auto& [nk, nv] : kv) {
        seen[stage][nk].insert(nv);
        ++has[stage][nk];
      }
    }
    std::map<std::string, std::set<std::string>> differ;
    for (const auto& [stage, keys] : seen)
      for (const auto& [nk, vals] : keys)
        if (vals.size() > 1 || has[stage][nk] != count[stage]) differ[stage].insert(nk);
    for (std::size_t i = 0; i < cases->size(); ++i) {
      std::string s;
      for (const auto& [nk, nv] : split[i].second)
        if (differ[split[i].first].count(nk)) s += (s.empty() ? "" : ", ") + nk + "=" + nv;
      (*cases)[i].shown.emplace_back(k, split[i].first + (s.empty() ? "" : "(" + s + ")"));
    }
  }
}

}  // namespace

std::string CanonicalStages(const std::vector<StageSpec>& stages) {
  std::string s;
  for (const auto& st : stages) {
    s += st.stage + "(";
    for (const auto& [k, v] : st.params.items()) s += k + "=" + FormatParamValue(v) + ";";
    s += ")";
  }
  return s;
}

std::string CaseKey(const Case& c, const DatasetSpec& ds, const std::string& metric_key) {
  const auto& nz = ds.normalize;
  return "item=" + c.source.Key() +
         (ds.kind == DatasetKind::kPoints ? "|points|ref=" + ds.reference : std::string()) +
         "|norm=" + std::to_string(nz.enabled) + "," + std::to_string(nz.longest_side) + "," +
         std::to_string(nz.center) + "," + std::to_string(nz.random_rotation) + "," +
         std::to_string(nz.rotation_seed) + "|input=" + c.input + ":" + CanonicalStages(c.input_stages) +
         "|method=" + c.method + ":" + CanonicalStages(c.method_stages) + "|metrics=" + metric_key +
         "|seed=" + std::to_string(c.seed) + (c.shared_method_seed ? "|method_seed=shared" : "");
}

std::vector<Case> ExpandCases(const Experiment& exp, const Registry& registry) {
  CheckCaseCount(exp);
  std::vector<Case> cases;
  std::vector<std::pair<std::string, std::vector<std::vector<StageSpec>>>> inputs;
  if (exp.inputs.empty()) inputs.push_back({"none", {{}}});
  for (const auto& in : exp.inputs) inputs.push_back({in.name, ExpandPipeline(in, registry)});
  std::vector<std::pair<std::string, std::vector<std::vector<StageSpec>>>> methods;
  for (const auto& m : exp.methods) methods.push_back({m.name, ExpandPipeline(m, registry)});
  std::vector<StageSpec> metrics;
  for (const auto& e : exp.metrics) {
    ParamMap given;
    for (const auto& [k, v] : e.values) given.Set(k, v.front());
    metrics.push_back(StageSpec{e.stage, registry.Resolve(e.stage, given)});
  }
  const std::string metric_key = CanonicalStages(metrics);

  for (const auto& ds : exp.datasets) {
    for (const auto& item : ds.items) {
      for (const auto& [in_name, in_variants] : inputs) {
        for (const auto& in_stages : in_variants) {
          for (const auto& [m_name, m_variants] : methods) {
            for (const auto& m_stages : m_variants) {
              Case c;
              c.dataset = ds.name;
              c.item = item.name;
              c.source = item;
              c.normalize = ds.normalize;
              c.reference_path = ds.reference;
              c.input = in_name;
              c.input_stages = in_stages;
              c.method = m_name;
              c.method_stages = m_stages;
              c.metric_stages = metrics;
              c.seed = exp.seed;
              c.shared_method_seed = exp.shared_method_seed;
              AddParamColumns(in_stages, &c.params);
              AddParamColumns(m_stages, &c.params);
              c.id = Hex16(Fnv1a64(CaseKey(c, ds, metric_key)));
              cases.push_back(std::move(c));
            }
          }
        }
      }
    }
  }
  // The same case twice (a file listed twice, overlapping globs): refused.
  {
    std::map<std::string, size_t> seen;
    for (size_t i = 0; i < cases.size(); ++i) {
      const auto [it, fresh] = seen.emplace(cases[i].id, i);
      if (!fresh)
        throw ExperimentError(exp.file + ": case " + cases[i].id + " appears twice (" + cases[it->second].source.Key() +
                              " | " + cases[i].input + " | " + cases[i].method +
                              "): an item listed twice in a dataset, or two datasets with the same files? each case runs once");
    }
  }
  MarkVarying(&cases);
  return cases;
}

}  // namespace arcs
