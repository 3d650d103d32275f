#include "app/stage_params.h"

#include "app/cli.h"

#include <memory>

namespace arcs {
namespace {

std::string Trim(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t") - b + 1);
}

// "a=1, b=f(c=2, d=3)" -> {"a=1", "b=f(c=2, d=3)"}: split at the commas
// outside parentheses.
std::vector<std::string> SplitTopLevel(const std::string& s, const std::string& what) {
  std::vector<std::string> out;
  int depth = 0;
  std::string cur;
  for (char c : s) {
    if (c == '(') ++depth;
    if (c == ')' && --depth < 0) cli::Usage(what + ": unbalanced ')' in '" + s + "'");
    if (c == ',' && depth == 0) {
      out.push_back(Trim(cur));
      cur.clear();
    } else {
      cur += c;
    }
  }
  if (depth != 0) cli::Usage(what + ": unbalanced '(' in '" + s + "'");
  out.push_back(Trim(cur));
  if (out.size() == 1 && out[0].empty()) out.clear();
  return out;
}

ParamValue DecodeValue(const Registry& registry, const ParamSpec& spec, const std::string& text,
                       const std::string& what) {
  ParamValue v;
  switch (spec.type) {
    case ParamType::kBool:
      if (text != "true" && text != "false") cli::Usage(what + " must be true or false, got '" + text + "'");
      v = text == "true";
      break;
    case ParamType::kInt: v = static_cast<std::int64_t>(cli::ParseInt64(text, what)); break;
    case ParamType::kDouble: v = cli::ParseDouble(text, what); break;
    case ParamType::kString:
    case ParamType::kChoice: v = text; break;
    case ParamType::kStage: {
      auto st = std::make_shared<StageSpec>();
      const size_t open = text.find('(');
      st->stage = Trim(text.substr(0, open));
      if (st->stage.empty()) cli::Usage(what + " needs a stage name, got '" + text + "'");
      if (!registry.Find(st->stage)) {
        try {
          registry.Get(st->stage);  // the registry's message (did you mean ...)
        } catch (const std::exception& e) {
          cli::Usage(what + ": " + e.what());
        }
      }
      if (open != std::string::npos) {
        const std::string body = Trim(text.substr(open));
        if (body.back() != ')') cli::Usage(what + ": expected STAGE(name=value, ...), got '" + text + "'");
        st->params = DecodeGivenParams(registry, st->stage,
                                       SplitTopLevel(body.substr(1, body.size() - 2), what), what);
      }
      v = st;
      break;
    }
  }
  return v;
}

}  // namespace

ParamMap DecodeGivenParams(const Registry& registry, const std::string& stage, const std::vector<std::string>& kvs,
                           const std::string& flag) {
  const StageInfo& info = registry.Get(stage);
  ParamMap given;
  for (const auto& kv : kvs) {
    const size_t eq = kv.find('=');
    if (eq == std::string::npos) cli::Usage(flag + " expects name=value, got '" + kv + "'");
    const std::string name = Trim(kv.substr(0, eq)), text = Trim(kv.substr(eq + 1));
    const ParamSpec* spec = info.params.Find(name);
    if (!spec) {
      std::string valid;
      for (const auto& p : info.params.specs()) valid += (valid.empty() ? "" : ", ") + p.name;
      cli::Usage(flag + ": stage '" + stage + "' has no parameter '" + name + "' (valid: " + valid + ")");
    }
    given.Set(name, DecodeValue(registry, *spec, text, flag + " " + stage + "." + name));
  }
  return given;
}

}  // namespace arcs
