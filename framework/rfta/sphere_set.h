// The spheres of Reach for the Arcs (paper §3): every SDF sample (p_i, s_i)
// is a sphere of centre p_i and radius |s_i|; a feasible surface touches every
// sphere without entering any.
//
// Frame. As the official code does, all RFTA stages work in the *unit frame*:
// the sample points are mapped into [0,1]^d by x' = (x - t) / scale with
// t = the per-axis minimum of the points and scale = the largest extent (over
// all axes), and the values are divided by scale. Every tolerance of the RFTA
// options (tol, sigma, ...) is in these [0,1] units, so they mean the same for
// every input scale. Stages map their outputs back to the input frame; the
// frame depends on the sample points only, so every stage computes the same.
//
// 2D (dim 2) samples are handled as 3D points with z = 0 throughout.
#pragma once

#include "framework/types.h"

#include <cstdint>
#include <string>
#include <vector>

namespace arcs {

// x_unit = (x - translation) / scale.
struct UnitFrame {
  int dim = 3;
  Vec3 translation = Vec3::Zero();  // per-axis minimum of the sample points (z = 0 in 2D)
  double scale = 1.0;               // largest extent of the sample points over all axes (> 0)

  Vec3 ToUnit(const Vec3& x) const { return (x - translation) / scale; }
  Vec3 FromUnit(const Vec3& u) const { return u * scale + translation; }
};

// Throws arcs::Error (prefixed with `who`) unless the samples are usable by
// RFTA: dim 2 or 3, as many points as values, at least 2 samples, all
// coordinates and values finite, and a bounding box that is not a point.
void CheckRftaSamples(const SdfSamples& samples, const std::string& who);

// The unit frame of the samples (CheckRftaSamples first).
UnitFrame ComputeUnitFrame(const SdfSamples& samples);

// The sample point i as a 3D point (z = 0 for dim 2).
Vec3 SamplePoint(const SdfSamples& samples, std::int64_t i);

// Spheres of one sign, in the unit frame.
struct SphereSet {
  int dim = 3;
  MatrixX3d centers;               // sphere centres (unit frame; z = 0 in 2D)
  VectorXd radii;                  // |s_i| / scale, > 0
  std::vector<int> sample;         // index of the SDF sample of each sphere
  // Whether the sphere wants a tangency point: false for clamped samples
  // (|s| >= clamp when samples.clamp > 0, paper §5.3): their sphere is still
  // empty of surface (a constraint, and rasterised) but touches nothing.
  std::vector<char> wants_point;
  int Size() const { return static_cast<int>(radii.size()); }
};

struct SignSplitOptions {
  // Samples with |s| / scale <= zero_radius carry no sphere (they are
  // skipped entirely). The official code counts s = 0 as positive and then
  // places a point at the centre with a made-up normal; a zero sample says
  // only "the surface passes here" and has no normal, so we drop it.
  double zero_radius = 1e-12;
  void Check() const;
};

// Paper §4.1 "Sign separation": the positive (s > 0, outside the shape) and
// negative (s < 0, inside) spheres are sampled, projected and made feasible
// apart, each against spheres of its own sign only.
struct SignedSpheres {
  UnitFrame frame;
  SphereSet positive;               // s > zero_radius * scale
  SphereSet negative;               // s < -zero_radius * scale
  std::int64_t num_samples = 0;     // all samples (the heuristics use this N)
  std::int64_t num_zero = 0;        // samples skipped as |s| <= zero_radius
  const SphereSet& Get(int sign) const { return sign > 0 ? positive : negative; }
};

// Splits the samples by sign into unit-frame spheres (CheckRftaSamples first).
// Does not require both signs to be present (see RequireBothSigns).
SignedSpheres SplitSpheresBySign(const SdfSamples& samples, const SignSplitOptions& options);

// Throws arcs::Error (prefixed with `who`) unless both signs have spheres:
// all-positive or all-negative samples contain no surface to reconstruct.
void RequireBothSigns(const SignedSpheres& spheres, const std::string& who);

// Inconsistent SDF data: positive and negative spheres that overlap by more
// than `tol` (unit frame). A true SDF never has any (the surface separates
// them); noisy SDFs (paper Fig. 23) have many small ones. Returns the number
// of positive spheres overlapping a negative one and, optionally, the largest
// overlap depth (unit frame).
std::int64_t CountSignConflicts(const SignedSpheres& spheres, double tol, double* max_depth = nullptr);

// n = N^(1/d), computed as the official Python does (N ** (1/d)).
double SamplesPerAxis(std::int64_t num_samples, int dim);

// The official rasterisation resolution (paper §4.1: r = 64 ceil(n / 16)),
// capped at `cap` (official: 1024) and made even.
int RasterResolutionHeuristic(std::int64_t num_samples, int dim, int cap = 1024);

// The official k_search = ceil(2 n) (paper §4.1).
int LocalSearchHeuristic(std::int64_t num_samples, int dim);

// The samples' spacing (input units): a grid's smallest node spacing, else
// the median distance from a sample to its nearest other sample (0 with
// fewer than 2 distinct samples). RFTA's `tuning_cell` is a fraction of it.
double SampleSpacing(const SdfSamples& samples);

// Free-space samples of both signs (the output of an empty-space sampler).
// sign[j] = +1: point j samples the free space of the positive spheres (it is
// outside all of them); -1: of the negative spheres.
struct FreeSpaceSamples {
  MatrixX3d points;                // input frame
  std::vector<signed char> sign;   // one per row of points
  std::int64_t Size() const { return points.rows(); }
};

// Concatenates per-sign unit-frame point sets into input-frame free samples.
FreeSpaceSamples MergeFreeSpace(const UnitFrame& frame, const MatrixX3d& positive_unit,
                                const MatrixX3d& negative_unit);

}  // namespace arcs
