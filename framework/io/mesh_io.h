// Triangle-mesh files: OBJ, OFF, PLY, STL (read and write).
//
// Every reader reports malformed input as arcs::InputError with the location:
// "FILE:LINE: what" for text, "FILE: offset N: what" for binary data. Readers
// never return non-finite coordinates or out-of-range indices, and check
// element counts from headers against the file size before allocating.
//
// Documented repairs (counted in MeshReadReport, never silent):
//  * polygons are fan-triangulated (v0 vi vi+1);
//  * OBJ/OFF coordinates written as exact rationals "p/q" are read as the
//    correctly rounded double of p/q (|p|, |q| <= 2^53);
//  * STL triangle soups are welded: corners with bit-identical positions
//    (+0 and -0 equal) become one vertex, numbered in order of first use.
// Kept as they are but counted: unreferenced vertices and degenerate faces
// (a triangle with a repeated vertex index). Zero-area triangles with
// distinct indices are not counted here (a geometric question).
//
// Format notes:
//  * OBJ: 'v' (x y z; a 4th value or colours ignored) and 'f' (i, i/t, i//n,
//    i/t/n; negative = relative) are read; vt vn vp g o s usemtl mtllib l p
//    and comments are ignored; other statements are ignored with a warning.
//  * OFF: OFF/COFF/NOFF/CNOFF/STOFF headers, '#' comments, counts "V F [E]"
//    on the header line or the next; one vertex / face per line, extra
//    values (colours, normals) ignored. Binary OFF is not supported.
//  * PLY: ascii / binary_little_endian / binary_big_endian, see ply.h.
//  * STL: binary when the size is exactly 84 + 50 n (n from the header),
//    whatever the first bytes say; ASCII otherwise.
#pragma once

#include "framework/types.h"

#include <string>
#include <vector>

namespace arcs {

struct MeshReadReport {
  int polygons_triangulated = 0;  // faces with more than 3 vertices, fan-triangulated
  int unreferenced_vertices = 0;  // vertices used by no face (kept)
  int degenerate_faces = 0;       // triangles with a repeated vertex index (kept)
  int rational_coordinates = 0;   // coordinate values written as "p/q"
  int welded_vertices = 0;        // STL corners merged into an earlier equal vertex
  std::vector<std::string> warnings;
};

// Reads .obj .off .ply .stl (extension, case-insensitive). Throws
// arcs::InputError for a missing file ("cannot open"), an unknown extension
// (listing the supported ones) or malformed content (with the location).
Mesh ReadMesh(const std::string& path, MeshReadReport* report = nullptr);

// Writes by extension: .obj / .off as ASCII with the shortest decimal that
// round-trips exactly; .ply binary little endian with double coordinates
// (exact); .stl binary (float32 coordinates: exact only for float-valued
// input; STL cannot store shared vertices, ReadMesh welds them back).
// Throws arcs::Error when the file cannot be written or the mesh is invalid
// (non-finite coordinates, indices out of range), InputError for an unknown
// extension.
void WriteMesh(const std::string& path, const Mesh& mesh);

// The extensions ReadMesh / WriteMesh accept, e.g. ".obj .off .ply .stl".
std::string SupportedMeshExtensions();

}  // namespace arcs
