// sdf_file: SDF samples loaded from a file (grid .npy, scattered .npy, text).
#include "framework/io/sdf_io.h"
#include "stages/builtin.h"

namespace arcs {

void RegisterSdfFile(Registry& r) {
  StageInfo s;
  s.name = "sdf_file";
  s.role = Role::kSdfSampler;
  s.doc = "SDF samples read from a file: grid .npy (+ .bounds sidecar), (N,d+1) .npy, or text 'x y z s'";
  s.params.String("path", "", "the file to read");
  s.factory = FunctionStage([](Context&, CaseData& d, const ParamMap& p) {
    const std::string& path = p.GetString("path");
    if (path.empty()) throw OptionError("sdf_file.path: must name a file");
    d.samples = ReadSdf(path);
  });
  r.Register(std::move(s));
}

}  // namespace arcs
