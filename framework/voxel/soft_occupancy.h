// Differentiable ("soft") occupancy of a triangle mesh from its winding number
// (Luo et al., "Differentiable Voxelization and Mesh Morphing", §2).
//
// Two discretisations of the winding number w(q) = 1/(4π) ∬ <n, (x-q)/|x-q|³> ds:
//  * kSolidAngle — Alg. 1 / eq. 5+7+8: the exact per-triangle solid angle,
//    Ω_f(q) = 2·atan2(α, β) with α = det(e0, e1, e2),
//    β = 1 + e0·e1 + e1·e2 + e2·e0, e_j = (v_j - q)/|v_j - q|
//    (Van Oosterom–Strackee; eq. 7 of the paper drops the factor 2 of the
//    half-angle formula, Alg. 1 sums atan2 and so means Ω/2 per face; we
//    return Ω/(4π) = atan2(α, β)/(2π) per face, i.e. w exactly). For a closed
//    mesh w is piecewise constant (0 / 1) away from the surface, so its
//    gradient with respect to the vertices vanishes there ("gradients
//    vanishing", §2.4): the per-face derivatives are non-zero but cancel.
//  * kNaive — eq. 4: one-point (centroid) quadrature of the integral,
//    w_f(q) = <N_f, c_f - q> / (4π |c_f - q|³) with N_f = n_f Δ_f the area
//    vector and c_f the centroid. Not exact near the surface (it blurs the step
//    over about one face size), but its gradient does not vanish: the paper
//    uses it for mesh morphing (§2.4, "a trade-off between the accuracy and
//    the differentiability").
//
// Softening (our addition to eq. 4, option `softening` ε, default 0 = the
// paper): near a face (distance ≪ face size) the eq. 4 term grows like Δ/d²,
// so w and its gradient blow up at grid nodes close to the surface when faces
// are about a voxel wide (measured: the morph of spot at 64³ diverged). With
// |r|³ replaced by (|r|² + ε²)^{3/2} — the field of a Plummer-softened point
// charge, whose divergence is the kernel 3ε²/(4π (r² + ε²)^{5/2}) of unit
// mass — w_ε is (up to the centroid quadrature) the indicator of the solid
// convolved with that kernel: bounded, a soft step of width ~ε, unchanged far
// from the surface.
//
// Occupancy from w: the paper takes occupancy = w (eq. 3, 5) and uses w
// directly in morphing (kIdentity, the default). kClamp and kSigmoid (with a
// sharpness s: o = 1/(1 + exp(-s (w - 1/2)))) are offered for experiments.
//
// Degenerate input: a query exactly on a vertex, or exactly at a face centroid
// (naive form), or with α = β = 0 contributes 0 to w and to the gradient for
// that face (the limit is undefined there); faces of zero area contribute 0.
#pragma once

#include "framework/types.h"
#include "framework/util/enum_names.h"

#include <string>

namespace arcs {

enum class WindingForm {
  kSolidAngle,  // Alg. 1 (atan2 solid angle), exact
  kNaive,       // eq. 4 (centroid quadrature), the paper's choice for morphing
};
// "solid_angle" | "naive"; ParseWindingForm throws OptionError for anything else.
const char* WindingFormName(WindingForm f);
WindingForm ParseWindingForm(const std::string& name);
// The names as the morph stage and `arcs morph --form` list them.
inline constexpr EnumName<WindingForm> kWindingFormNames[] = {{WindingForm::kNaive, "naive"},
                                                             {WindingForm::kSolidAngle, "solid_angle"}};

// Per-triangle winding-number contribution w_f(q) (solid angle / 4π, or the
// eq. 4 term), and, when `grad` is not null, its derivatives with respect to
// the three corners: grad[j] = ∂w_f/∂v_j. (∂w_f/∂q = -Σ_j grad[j].)
double SolidAngleTermGrad(const Vec3& v0, const Vec3& v1, const Vec3& v2, const Vec3& q,
                          Vec3* grad);
// `softening` ε replaces |r|³ by (|r|² + ε²)^{3/2} (0 = eq. 4 exactly).
double NaiveTermGrad(const Vec3& v0, const Vec3& v1, const Vec3& v2, const Vec3& q, Vec3* grad,
                     double softening = 0.0);
inline double WindingTermGrad(WindingForm form, const Vec3& v0, const Vec3& v1, const Vec3& v2,
                              const Vec3& q, Vec3* grad, double softening = 0.0) {
  return form == WindingForm::kSolidAngle ? SolidAngleTermGrad(v0, v1, v2, q, grad)
                                          : NaiveTermGrad(v0, v1, v2, q, grad, softening);
}

// w(q) for every row of Q: the dense sum over all faces, parallel over
// queries, deterministic (per-query outputs; faces summed in order). The
// solid-angle form calls WindingNumbersExact. Throws InputError for face
// indices out of range or non-finite vertices.
VectorXd WindingNumbers(const Mesh& mesh, const MatrixX3d& Q, WindingForm form, double softening = 0.0);

enum class OccupancyMap {
  kIdentity,  // o = w (the paper)
  kClamp,     // o = clamp(w, 0, 1)
  kSigmoid,   // o = σ(s (w - 1/2))
};
const char* OccupancyMapName(OccupancyMap m);
OccupancyMap ParseOccupancyMap(const std::string& name);  // "identity" | "clamp" | "sigmoid"
inline constexpr EnumName<OccupancyMap> kOccupancyMapNames[] = {
    {OccupancyMap::kIdentity, "identity"}, {OccupancyMap::kClamp, "clamp"}, {OccupancyMap::kSigmoid, "sigmoid"}};

struct SoftOccupancyOptions {
  WindingForm form = WindingForm::kNaive;  // eq. 4, as the paper's morphing
  OccupancyMap map = OccupancyMap::kIdentity;  // the paper: occupancy = w
  double sharpness = 10.0;  // s of kSigmoid (1/s = width of the soft step in w); unused otherwise
  // Naive form only: ε of the softened kernel (|r|² + ε²)^{-3/2} (our addition;
  // 0 = eq. 4 exactly). See the note at the top.
  double softening = 0.0;
  void Check() const;       // sharpness finite and > 0, softening finite and >= 0
};

// o = φ(w) and, when `dodw` is not null, φ'(w).
double OccupancyFromWinding(double w, const SoftOccupancyOptions& options, double* dodw);

// Soft occupancy φ(w(q)) at every row of Q.
VectorXd SoftOccupancy(const Mesh& mesh, const MatrixX3d& Q, const SoftOccupancyOptions& options);

}  // namespace arcs
