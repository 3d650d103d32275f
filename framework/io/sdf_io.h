// Signed-distance samples (arcs::SdfSamples) from and to files.
//
// Grid files (.npy, values only)
//   A 3D array of shape (nx, ny, nz), or a 2D array (nx, ny), where
//   arr[i, j, k] is the value at (x_i, y_j, z_k) with
//   x_i = numpy.linspace(min[0], max[0], nx)[i] (likewise y, z) — i.e. what
//   `f(*np.meshgrid(x, y, z, indexing='ij'))` gives. It is converted to the
//   arcs order of GridInfo (x fastest: index = i + nx * (j + ny * k)) and the
//   sample points are filled in, bitwise equal to numpy's linspace.
//   Bounds sidecar: when a text file "<values_npy>.bounds" exists (e.g.
//   "sdf.npy.bounds"), it overrides the min/max arguments. It holds
//   "xmin ymin zmin xmax ymax zmax" (3D) or "xmin ymin xmax ymax" (2D),
//   whitespace separated, '#' comments allowed. WriteSdfGrid writes it.
//
// Scattered files (.npy pair): points (N, 3) or (N, 2), values (N,) or (N, 1).
//
// Text files (.txt .xyzs .sdf): one sample per line, "x y z s" (3D) or
//   "x y s" (2D); the first data line decides, later lines must match; '#'
//   comments and blank lines are allowed.
//
// ReadSdf dispatch rule (by extension, then by array shape):
//   .txt .xyzs .sdf        -> text
//   .npz                   -> 'U'/'S'/'bounds' members (see WriteSdfNpz)
//   .npy of ndim 3         -> 3D grid (default bounds [-1, 1]^3 or the sidecar)
//   .npy of shape (N, 4)   -> scattered 3D: columns x y z s   } unless a .bounds
//   .npy of shape (N, 3)   -> scattered 2D: columns x y s     } sidecar exists
//   .npy of other ndim 2   -> 2D grid (default bounds [-1, 1]^2 or the sidecar)
//   A 2D grid with 3 or 4 columns therefore needs its .bounds sidecar (or
//   ReadSdfGrid) to be read as a grid. Anything else is an InputError that
//   lists the accepted shapes.
//
// Every reader rejects NaN / inf values and points (InputError naming the
// sample, or the line for text). SdfSamples::clamp is not stored by any
// format and reads back as 0.
#pragma once

#include "framework/io/npy.h"
#include "framework/types.h"

#include <array>
#include <string>

namespace arcs {

SdfSamples ReadSdfGrid(const std::string& values_npy,
                       const std::array<double, 3>& min = {-1, -1, -1},
                       const std::array<double, 3>& max = {1, 1, 1});

// Grid samples from values in numpy C order (shape (nx, ny, nz) or (nx, ny))
// and bounds: the .npy reader's conversion, for arrays from other sources
// (.npz members, the Python module). `path` names the source in errors,
// `bounds_origin` where min/max came from.
SdfSamples SdfGridFromArray(const std::string& path, const NpyArray& arr, std::array<double, 3> min,
                            std::array<double, 3> max, const std::string& bounds_origin = "the default bounds");

// Writes s (which must have s.grid) as an (nx, ny[, nz]) '<f8' array in the
// numpy index order above, and the "<values_npy>.bounds" sidecar.
void WriteSdfGrid(const std::string& values_npy, const SdfSamples& s);

SdfSamples ReadSdfScattered(const std::string& points_npy, const std::string& values_npy);

SdfSamples ReadSdfText(const std::string& path);
// Writes "x y z s" (or "x y s") lines with shortest round-trip decimals.
void WriteSdfText(const std::string& path, const SdfSamples& s);

// .npz (numpy.savez): 'U' (N, d) points and 'S' (N,) values, or 'S' a grid
// (nx, ny[, nz]) in the .npy grid layout with 'bounds' (2, d) = [min, max]
// (default [-1, 1]^d; 'U' then holds the nodes in meshgrid 'ij' order and is
// not needed to read it). WriteSdfNpz writes U, S (+ bounds for a grid).
void WriteSdfNpz(const std::string& path, const SdfSamples& s);

// Writes by extension: .npy (a grid as WriteSdfGrid, scattered samples as an
// (N, d+1) array of rows 'x y z s', which ReadSdf reads back), .npz, text
// (.txt .xyzs .sdf). Another extension is an InputError listing these.
void WriteSdf(const std::string& path, const SdfSamples& s);

// Convenience dispatch, see the rule above; .npz as described above.
SdfSamples ReadSdf(const std::string& path);

// The sidecar path for a grid file: values_npy + ".bounds".
std::string SdfBoundsPath(const std::string& values_npy);

}  // namespace arcs
