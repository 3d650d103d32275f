// Analytic shapes the project makes itself (no data files needed): used by the
// README's main job, by tests and as built-in dataset items ("shape:torus").
#pragma once

#include "framework/types.h"

#include <string>
#include <vector>

namespace arcs {

// Icosphere of radius r centred at c: `subdivisions` loop-free midpoint
// subdivisions of an icosahedron (20 * 4^s faces).
Mesh MakeIcosphere(double radius = 1.0, int subdivisions = 4, const Vec3& center = Vec3::Zero());

// Torus around the z axis: major radius R, tube radius r, nu x nv quads
// split into triangles. Defaults match the official measurements' torus
// (R = 0.35, r = 0.15, 400 x 200 quads).
Mesh MakeTorus(double R = 0.35, double r = 0.15, int nu = 400, int nv = 200);

// A (p, q) torus knot tube: centre curve on a torus of radii (R, a), tube
// radius r; nu samples along the curve, nv around the tube.
Mesh MakeTorusKnot(int p = 2, int q = 3, double R = 0.3, double a = 0.12, double r = 0.06,
                   int nu = 600, int nv = 48);

// Concatenates meshes (no welding).
Mesh Concatenate(const std::vector<Mesh>& parts);

// A built-in shape by name: sphere, torus, knot, two_tori. Throws Error
// listing the names for an unknown one.
Mesh MakeBuiltinShape(const std::string& name);
std::vector<std::string> BuiltinShapeNames();

}  // namespace arcs
