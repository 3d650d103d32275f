// Point clouds (arcs::PointCloud) from and to files.
//
// Reading (by extension, case-insensitive):
//  * .ply  ascii / binary: vertex x y z, optional nx ny nz (or normal_x …);
//          faces and other elements are skipped.
//  * .xyz .pwn .txt  "x y z" or "x y z nx ny nz" per line. As in the graph-
//          Voronoi paper's loader, malformed lines (wrong column count, not
//          numbers) are skipped and their line numbers reported; the column
//          count (3 or 6) of the first valid line decides, lines with the
//          other count are skipped too. '#' comments and blank lines are not
//          reported. No valid line at all -> InputError.
//  * .pcd  DATA ascii, binary or binary_compressed (LZF, as PCL and Open3D
//          write it; framework/io/lzf.h); fields x y z, optional normal_x
//          normal_y normal_z, other fields skipped.
// Points with a non-finite coordinate or normal (e.g. PCD's NaN placeholders
// of organised clouds) are skipped and reported: their line in
// skipped_lines for text data, a warning with a count and the first byte
// offset for binary data. Normals are returned as stored (not renormalised).
#pragma once

#include "framework/types.h"

#include <string>
#include <vector>

namespace arcs {

struct PointReadReport {
  std::vector<long> skipped_lines;    // 1-based lines skipped (malformed or non-finite)
  std::vector<std::string> warnings;  // one line each, human readable
};

PointCloud ReadPointCloud(const std::string& path, PointReadReport* report = nullptr);

// .ply: binary little endian, double x y z (+ nx ny nz when pc has normals),
// exact. .xyz (.pwn, .txt): "x y z [nx ny nz]" with shortest round-trip
// decimals. Throws arcs::Error when the file cannot be written.
void WritePointCloud(const std::string& path, const PointCloud& pc);

}  // namespace arcs
