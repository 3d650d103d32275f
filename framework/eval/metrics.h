// Surface-comparison metrics of the RFTA evaluation protocol (paper
// Section 5 / scripts/fig_many-shapes-experiment.py), and better-founded
// variants, clearly named.
//
// Every metric throws arcs::Error("...: mesh ... is empty") when a mesh has
// no faces (a metric stage records this as a failed case rather than writing
// an infinite number into a table), and on zero-area meshes where sampling is
// needed. Sample counts must be >= 1.
#pragma once

#include "framework/types.h"

#include <cstdint>

namespace arcs {

// The setting of the sampled metrics (ChamferPaper, ChamferPointToSurface,
// HausdorffSampled) as their stages take it.
struct SampledMetricOptions {
  std::int64_t samples = 1000000;  // area-uniform samples per mesh, in [1, 1e8] (paper: 10^6)
  void Check() const;              // OptionError naming the field
};

// The paper's Chamfer distance: `samples` area-uniform points on each mesh,
// d1 = distance of each sample of A to the nearest *sample* of B (kd-tree),
// d2 likewise from B to A; returns sqrt(mean d1^2) + sqrt(mean d2^2) (the sum
// of two RMS values, neither squared nor halved). The two sample sets use
// independent seeds derived from `seed`, so Chamfer(A, A) is the sampling
// floor (about 0.0016 for a unit-size torus at 10^6 samples), not 0.
double ChamferPaper(const Mesh& a, const Mesh& b, std::int64_t samples = 1000000,
                    std::uint64_t seed = 1);

// The paper's Hausdorff distance (igl::hausdorff): the max over the vertices
// of each mesh of the exact distance to the other mesh's surface. A lower
// bound of the true Hausdorff distance. Only vertices referenced by a face
// count.
double HausdorffPaper(const Mesh& a, const Mesh& b);

// The paper's SDF energy: 1000 * mean_i (|s_i| - dist(p_i, m))^2 with dist the
// unsigned distance to the mesh's surface. When samples.clamp > 0, samples
// with |s_i| >= clamp are skipped (their true distance is unknown); if all
// are skipped the result is 0. 3D samples only.
double EnergySdf(const SdfSamples& samples, const Mesh& m);

// Point-to-surface Chamfer (better founded than ChamferPaper: no sampling of
// the target): `samples` area-uniform points on each mesh, distance to the
// other mesh's *surface* (closest point on its triangles); same formula
// sqrt(mean d1^2) + sqrt(mean d2^2). Chamfer(A, A) = 0 exactly.
double ChamferPointToSurface(const Mesh& a, const Mesh& b, std::int64_t samples = 1000000,
                             std::uint64_t seed = 1);

// Two-sided sampled Hausdorff: the max over `samples` surface samples and the
// referenced vertices of each mesh of the distance to the other surface.
// Still a lower bound, but much tighter than HausdorffPaper on coarse meshes.
double HausdorffSampled(const Mesh& a, const Mesh& b, std::int64_t samples = 1000000,
                        std::uint64_t seed = 1);

}  // namespace arcs
