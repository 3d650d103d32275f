// Normalisation of a shape into the evaluation frame of the RFTA paper: the
// bounding box is centred at the origin, its longest side is scaled to 1, and
// (optionally) the shape is given a random rotation about the origin.
#pragma once

#include "framework/types.h"

#include <Eigen/Core>

#include <cstdint>

namespace arcs {

struct NormalizeOptions {
  bool center = true;               // move the bounding-box centre to the origin
  double longest_side = 1.0;        // the longest bounding-box side becomes this (paper: 1); 0 = keep the scale
  bool random_rotation = false;     // the paper's many-shapes script rotates after scaling
  std::uint64_t rotation_seed = 1;  // seed of the rotation draw (paper: numpy seed 1; see Normalize)
  void Check() const;
};

// A similarity transform  x' = scale * R * (x + translation)  (translate
// first, then scale and rotate about the origin). This is the order of the
// paper's normalisation: centre, scale, then rotate.
struct Similarity {
  double scale = 1.0;
  Vec3 translation = Vec3::Zero();
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();

  Vec3 Apply(const Vec3& x) const { return scale * (rotation * (x + translation)); }
  Vec3 ApplyInverse(const Vec3& y) const {
    return rotation.transpose() * y / scale - translation;
  }
  // The inverse, in the same form: x = (1/s) R^T (y + (-s R t)).
  Similarity Inverse() const;
  // Distances scale by `scale` (rotation and translation preserve them).
  double ScaleDistance(double d) const { return scale * d; }
};

// The transform that Normalize would apply to points `V` (bounding box over
// all rows of V). Throws arcs::Error if V is empty or, when scaling, if the
// bounding box is a single point.
//
// Random rotation, as the paper's script draws it: axis = (u0, u1, u2)
// normalised with u ~ U(0,1), angle = 2*pi*u3, from arcs::Rng(rotation_seed)
// in that order. numpy's stream cannot be reproduced, so the rotation differs
// from the paper's for the same seed; only its distribution is the same (note
// that the axis lies in the positive octant, as in the paper).
Similarity NormalizeTransform(const MatrixX3d& V, const NormalizeOptions& options);

// Normalises `mesh` in place and returns the applied transform.
Similarity Normalize(Mesh* mesh, const NormalizeOptions& options);

void ApplySimilarity(const Similarity& t, MatrixX3d* points);
Mesh ApplySimilarity(const Similarity& t, const Mesh& mesh);
Mesh ApplyInverseSimilarity(const Similarity& t, const Mesh& mesh);

// Transforms 3D SDF samples: points are mapped, values (and clamp) are
// multiplied by the scale. A grid layout stays valid only without rotation;
// with a non-identity rotation the grid is dropped (points keep their order).
void ApplySimilarity(const Similarity& t, SdfSamples* samples);

}  // namespace arcs
