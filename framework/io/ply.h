// Internal PLY reader shared by ReadMesh and ReadPointCloud.
//
// Supports "format ascii | binary_little_endian | binary_big_endian 1.0",
// every scalar type (char/int8 … double/float64), list properties with any
// integer count and item types, and skips unknown properties and elements.
// Only the 'vertex' element (x y z, optional nx ny nz or normal_x normal_y
// normal_z) and the 'face' element (list 'vertex_indices' or 'vertex_index')
// are interpreted. Element counts are never trusted for allocation: binary
// counts are checked against the bytes left (a lying header fails at once, at
// its header line); ASCII reserves at most what the remaining text could
// hold, and a short file fails at the line where its data runs out.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace arcs::io_internal {

struct PlyRequest {
  bool want_normals = false;
  bool want_faces = false;
  // true: a non-finite vertex coordinate throws InputError at its location;
  // false: it is recorded in PlyData::nonfinite and reading goes on.
  bool nonfinite_is_error = true;
};

struct PlyData {
  bool binary = false;
  std::int64_t num_vertices = 0;
  std::vector<double> xyz;      // 3 per vertex
  bool has_normals = false;
  std::vector<double> normals;  // 3 per vertex when has_normals
  bool has_faces = false;       // a face element with a vertex index list exists
  std::vector<int> triangles;   // 3 per triangle (polygons fan-triangulated)
  int polygons_triangulated = 0;
  // Vertices with a non-finite position (or normal): index and location
  // (line for ASCII, byte offset for binary). Only when !nonfinite_is_error.
  struct Bad {
    std::int64_t index;
    std::uint64_t location;
  };
  std::vector<Bad> nonfinite;
  std::vector<std::string> warnings;
};

PlyData ReadPly(const std::string& path, std::string_view bytes, const PlyRequest& request);

}  // namespace arcs::io_internal
