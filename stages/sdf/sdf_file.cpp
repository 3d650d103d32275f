// sdf_file: SDF samples loaded from a file (grid .npy, scattered .npy, text).
#include "framework/io/sdf_io.h"
#include "stages/builtin.h"

namespace arcs {

namespace {

void RunSdfFile(Context&, CaseData& d, const ParamMap& p) {
  const std::string& path = p.GetString("path");
  if (path.empty()) throw OptionError("sdf_file.path: must name a file");
  d.samples = ReadSdf(path);
}

}  // namespace

void RegisterSdfFile(Registry& r) {
  // No Options struct (the path is the whole setting): the schema as is.
  StageInfo s = DeclareStage(
      "sdf_file", Role::kSdfSampler,
      "SDF samples read from a file: grid .npy (+ .bounds sidecar), (N,d+1) .npy, or text 'x y z s'", {},
      {Slot::kSamples}, kAnyDim);
  s.params.String("path", "", "the file to read");
  s.factory = FunctionStage(RunSdfFile);
  r.Register(std::move(s));
}

}  // namespace arcs
