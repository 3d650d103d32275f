// Helpers shared by the point-cloud reconstructors (plain code, no
// third-party types): the point spacing that sets the default radii, input
// validation and cleaning, and output post-processing.
#pragma once

#include "framework/types.h"

#include <string>

namespace arcs {

// The point spacing h: mean distance from a point to its nearest other point,
// over an evenly strided subsample of at most 4096 points (deterministic).
// For n area-uniform random samples of a surface of area A, h ~ 0.5 sqrt(A/n)
// (the 2D Poisson process). Coincident points are skipped (their distance 0
// would say nothing about the sampling). Throws Error when fewer than 2
// distinct points.
double PointSpacing(const MatrixX3d& P);

struct PreparedPoints {
  PointCloud cloud;            // finite, distinct positions; unit normals if kept
  int duplicates_removed = 0;  // rows dropped because an earlier row has the same position
};

// Validates and cleans the input of reconstructor `who` (its name starts
// every message):
//  * Error when `in` has fewer than `min_points` rows, a non-finite
//    coordinate (naming the row), or — with `need_normals` — no normals
//    ("... needs oriented points: add estimate_normals to the input
//    pipeline"), a non-finite or zero normal (naming the row).
//  * Points at exactly the same position as an earlier one are dropped (the
//    first is kept) and counted: Delaunay-based methods would merge them
//    anyway and ball pivoting can create degenerate triangles on them.
//  * Error when fewer than `min_points` distinct points remain.
// Normals are normalised; with need_normals = false they are kept when
// present and valid (used to orient open outputs) and dropped otherwise.
PreparedPoints PrepareReconstructionInput(const PointCloud& in, const std::string& who, bool need_normals,
                                          int min_points = 4);

// Orients every connected component (faces sharing a vertex) of a mesh whose
// components are each consistently oriented: a closed component is flipped
// if its signed volume is negative; an open one is flipped if most of its
// area faces against the vertex normals `vertex_normals` (rows of V), when
// given. Returns the number of components flipped.
int OrientComponents(Mesh* mesh, const MatrixX3d* vertex_normals);

// Drops vertices that no face uses (keeps order) and faces with a repeated
// vertex index.
Mesh CompactMesh(const Mesh& mesh);

}  // namespace arcs
