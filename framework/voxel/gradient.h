// Gradients of winding numbers, soft occupancy and occupancy losses with
// respect to the mesh vertices (Luo et al. §2.4: differentiable voxelization
// for mesh morphing).
//
// Everything is the dense sum over all faces × queries (O(#F · #Q)); callers
// that need speed pass fewer queries (see morph.h for the active-set
// sampling). Parallel and deterministic: the forward pass writes per-query
// values; the adjoint pass runs over fixed blocks of faces, each face summing
// over the queries in their order, then scatters to vertices in face order —
// the same bits at any thread count.
#pragma once

#include "framework/types.h"
#include "framework/util/enum_names.h"
#include "framework/voxel/soft_occupancy.h"

#include <string>

namespace arcs {

// Vector–Jacobian product Σ_q λ_q ∂w(q)/∂V (#V x 3) for the given form.
// Queries with λ_q = 0 are skipped. λ.size() must equal Q.rows().
// `softening` is the ε of the naive form (see soft_occupancy.h; ignored by
// the solid-angle form).
MatrixX3d WindingNumberVjp(const Mesh& mesh, const MatrixX3d& Q, const VectorXd& lambda,
                           WindingForm form, double softening = 0.0);

enum class OccupancyLossKind {
  kMse,  // mean (o - t)²: the default (the paper does not name its loss; MSE works with o = w)
  kBce,  // mean binary cross-entropy, o clipped to [1e-6, 1 - 1e-6] (needs o in (0, 1): use
         // the clamp or sigmoid map)
};
const char* OccupancyLossName(OccupancyLossKind k);
OccupancyLossKind ParseOccupancyLoss(const std::string& name);  // "mse" | "bce"
inline constexpr EnumName<OccupancyLossKind> kOccupancyLossNames[] = {{OccupancyLossKind::kMse, "mse"},
                                                                     {OccupancyLossKind::kBce, "bce"}};

struct OccupancyLossOptions {
  SoftOccupancyOptions occupancy;  // form (naive = eq. 4) and occupancy map (identity = paper)
  OccupancyLossKind loss = OccupancyLossKind::kMse;
  void Check() const { occupancy.Check(); }
};

struct OccupancyLossResult {
  double loss = 0.0;   // mean over the queries
  MatrixX3d grad;      // ∂loss/∂V, #V x 3
  VectorXd winding;    // w(q) per query (form of the options)
  VectorXd occupancy;  // φ(w(q)) per query
};

// Loss between the soft occupancy of `mesh` at Q and `target` (one value per
// query, in [0, 1]; typically 0/1), and its gradient with respect to the
// vertices. Throws Error if target.size() != Q.rows() or Q is empty.
OccupancyLossResult OccupancyLoss(const Mesh& mesh, const MatrixX3d& Q, const VectorXd& target,
                                  const OccupancyLossOptions& options);

// Per-query loss value and dℓ/do (not divided by the number of queries).
double OccupancyLossTerm(double o, double t, OccupancyLossKind kind, double* dldo);

}  // namespace arcs
