// 2D shapes as closed polylines (arcs::Polyline, z = 0), their files, and
// basic facts about them.
//
// Orientation (types.h): the inside lies to the left of every edge, so an
// outer boundary runs counter-clockwise and a hole's boundary clockwise.
//
// Polyline files (.obj, .txt, .poly; read and written): the OBJ subset for
// polylines, one element per line, '#' comments and blank lines allowed:
//   v X Y [Z]        a vertex (Z, when present, must be 0: a 2D curve)
//   l I1 I2 ... Ik   a chain of edges I1->I2->...->Ik, 1-based vertex indices
//                    (negative = relative to the last vertex, as OBJ); a closed
//                    curve repeats I1 at the end
//   o/g/s/usemtl/... ignored; `f` (faces) is an error (not a curve file)
// WritePolyline writes every chain as one `l` line (closed chains end with
// their first index). `.svg` is write-only (for viewing; y points up).
// Every malformed line is an InputError "FILE:LINE: what".
#pragma once

#include "framework/geometry/marching_cubes.h"
#include "framework/types.h"

#include <string>
#include <vector>

namespace arcs {

// A built-in curve by name (see BuiltinCurveNames), about `segments` edges in
// all (>= 16), fitting [-0.5, 0.5]^2 with longest side close to 1:
//   circle      radius 0.5
//   ellipse     semi-axes 0.5 x 0.3
//   star        five-petal flower r = 0.32 (1 + 0.55 cos 5t) (smooth, deep concavities)
//   bunny       a head with two long ears (non-convex, narrow gap between the ears)
//   letter_c    a thick "C" with round ends (non-convex, a narrow mouth)
//   square      axis-aligned square of side 0.8 (sharp corners)
//   two_circles two disjoint discs (two components)
//   annulus     disc of radius 0.5 with a hole of radius 0.25 (inner curve clockwise)
// Throws Error listing the names for an unknown one.
Polyline MakeBuiltinCurve(const std::string& name, int segments = 1024);
std::vector<std::string> BuiltinCurveNames();

// A closed polygon through `points` (k x 2 or k x 3 with z ignored), in order.
Polyline MakeClosedPolyline(const MatrixXd& points);

// Moves the bounding-box centre to the origin (when `center`) and scales the
// longest bounding-box side to `longest_side` (> 0; when the curve has a
// positive extent). The dataset normalisation of 2D cases.
void NormalizeCurve(Polyline* curve, double longest_side = 1.0, bool center = true);

// Throws InputError (prefixed with `who`) unless the curve has >= 1 edge,
// finite coordinates, z = 0 and valid edge indices.
void CheckPolyline(const Polyline& curve, const std::string& who);

// Total edge length.
double PolylineLength(const Polyline& curve);
// Signed enclosed area (shoelace over the edges): > 0 for counter-clockwise
// outer boundaries; a hole subtracts.
double PolylineSignedArea(const Polyline& curve);

// Structure of the edge graph.
struct CurveTopology {
  int components = 0;         // connected components of the edge graph (vertices without edges ignored)
  int closed_components = 0;  // components where every vertex has one incoming and one outgoing edge
  int open_ends = 0;          // vertices with exactly one incident edge
  int branch_vertices = 0;    // vertices with more than two incident edges, or two edges pointing the same way
  int holes = 0;              // closed components with negative signed area (clockwise)
  bool Closed() const { return components > 0 && closed_components == components; }
};
CurveTopology ComputeCurveTopology(const Polyline& curve);

// Reads a polyline file (format above). Throws InputError (file:line).
Polyline ReadPolyline(const std::string& path);
// Writes .obj/.txt/.poly (format above) or .svg (by extension; others are an
// Error). Throws Error when the file cannot be written.
void WritePolyline(const std::string& path, const Polyline& curve);

// The marching-squares result (framework/geometry) as a Polyline (z = 0).
Polyline ToPolyline(const Polyline2& p);

}  // namespace arcs
