// Dataset items, typed: what one case loads as its reference (a mesh file, a
// built-in shape, a 2D curve file or built-in curve) or as its points (a point
// cloud file). Items are made once, where the experiment's `datasets:` are
// decoded (DecodeDatasetItems); everything after it (case expansion, case
// execution, the saved config.resolved.yaml) switches on the kind instead of
// parsing "shape:"/"curve:" prefixes.
#pragma once

#include <string>
#include <vector>

namespace arcs {

// What a dataset's files are (`kind:` in the YAML).
enum class DatasetKind {
  kMesh,    // meshes (or built-in shapes), loaded as the case's reference
  kPoints,  // point clouds (PLY/XYZ/PWN/PCD), loaded as the case's points
  kCurves,  // 2D polylines (or built-in curves), loaded as the reference curve
};
// "mesh" | "points" | "curves" (the YAML names).
const char* DatasetKindName(DatasetKind k);
// The kind named `name`; false if it names none.
bool ParseDatasetKind(const std::string& name, DatasetKind* out);

enum class ItemKind {
  kMeshFile,      // path: a mesh file
  kBuiltinShape,  // name: a built-in shape (BuiltinShapeNames)
  kPointFile,     // path: a point cloud file
  kCurveFile,     // path: a 2D polyline file
  kBuiltinCurve,  // name: a built-in curve (BuiltinCurveNames)
};

struct DatasetItem {
  ItemKind kind = ItemKind::kMeshFile;
  std::string path;  // the resolved file (file kinds); "" for built-ins
  std::string name;  // the built-in's name, or the file's stem: the results' `item`

  bool IsBuiltin() const { return kind == ItemKind::kBuiltinShape || kind == ItemKind::kBuiltinCurve; }
  DatasetKind Dataset() const;  // the kind of dataset this item belongs to
  // The item's identity in case ids, random streams and CaseData::item_path:
  // the file's path, or "shape:NAME" / "curve:NAME" for built-ins (the text
  // used before items were typed, so case ids and results are unchanged).
  std::string Key() const;
  // What errors call it: the path, or "built-in shape 'torus'".
  std::string Describe() const;
};

// A file item of a dataset of kind `k` (a mesh, point or curve file).
DatasetItem FileItem(DatasetKind k, const std::string& path);
// A built-in item of a dataset of kind `k`: a built-in shape (kMesh) or curve
// (kCurves). Throws Error naming the valid names (with "did you mean") for an
// unknown name, or for kPoints (no built-in point clouds).
DatasetItem BuiltinItem(DatasetKind k, const std::string& name);

}  // namespace arcs
