#include "orchestration/items.h"

#include "framework/error.h"
#include "framework/geometry/builtin_shapes.h"
#include "framework/geometry/curves.h"
#include "framework/util/suggest.h"

#include <algorithm>
#include <filesystem>

namespace arcs {

const char* DatasetKindName(DatasetKind k) {
  switch (k) {
    case DatasetKind::kMesh: return "mesh";
    case DatasetKind::kPoints: return "points";
    case DatasetKind::kCurves: return "curves";
  }
  return "?";
}

bool ParseDatasetKind(const std::string& name, DatasetKind* out) {
  for (DatasetKind k : {DatasetKind::kMesh, DatasetKind::kPoints, DatasetKind::kCurves})
    if (name == DatasetKindName(k)) {
      *out = k;
      return true;
    }
  return false;
}

DatasetKind DatasetItem::Dataset() const {
  switch (kind) {
    case ItemKind::kMeshFile:
    case ItemKind::kBuiltinShape: return DatasetKind::kMesh;
    case ItemKind::kPointFile: return DatasetKind::kPoints;
    case ItemKind::kCurveFile:
    case ItemKind::kBuiltinCurve: return DatasetKind::kCurves;
  }
  return DatasetKind::kMesh;
}

std::string DatasetItem::Key() const {
  switch (kind) {
    case ItemKind::kBuiltinShape: return "shape:" + name;
    case ItemKind::kBuiltinCurve: return "curve:" + name;
    default: return path;
  }
}

std::string DatasetItem::Describe() const {
  switch (kind) {
    case ItemKind::kBuiltinShape: return "built-in shape '" + name + "'";
    case ItemKind::kBuiltinCurve: return "built-in curve '" + name + "'";
    default: return path;
  }
}

DatasetItem FileItem(DatasetKind k, const std::string& path) {
  DatasetItem it;
  it.kind = k == DatasetKind::kPoints ? ItemKind::kPointFile
            : k == DatasetKind::kCurves ? ItemKind::kCurveFile
                                        : ItemKind::kMeshFile;
  it.path = path;
  it.name = std::filesystem::path(path).stem().string();
  return it;
}

DatasetItem BuiltinItem(DatasetKind k, const std::string& name) {
  if (k == DatasetKind::kPoints)
    throw Error("built-in shapes are meshes; a 'kind: points' dataset needs 'files'");
  const bool curve = k == DatasetKind::kCurves;
  const std::vector<std::string> names = curve ? BuiltinCurveNames() : BuiltinShapeNames();
  if (std::find(names.begin(), names.end(), name) == names.end()) {
    std::string valid;
    for (const auto& b : names) valid += (valid.empty() ? "" : ", ") + b;
    throw Error(std::string("unknown built-in ") + (curve ? "curve" : "shape") + " '" + name + "'" +
                DidYouMean(name, names) + "; valid: " + valid);
  }
  DatasetItem it;
  it.kind = curve ? ItemKind::kBuiltinCurve : ItemKind::kBuiltinShape;
  it.name = name;
  return it;
}

}  // namespace arcs
