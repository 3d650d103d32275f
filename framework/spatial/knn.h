// k-nearest-neighbour queries on 3D point sets (kd-tree).
#pragma once

#include "framework/types.h"

#include <memory>
#include <vector>

namespace arcs {

// Permutation of the rows of P along a Morton (Z-order) curve over their
// bounding box (10 bits per axis; rows in one cell keep index order).
// Processing queries in this order makes consecutive queries neighbours,
// which batch queries use for cache reuse and warm starts. Deterministic.
std::vector<int> MortonOrder(const MatrixX3d& P);

class KdTree3 {
 public:
  // Indexes the rows of P (copied).
  explicit KdTree3(const MatrixX3d& P);
  ~KdTree3();
  KdTree3(KdTree3&&) noexcept;
  KdTree3& operator=(KdTree3&&) noexcept;

  int Size() const;
  // Index of the nearest point to q (ties: lowest index); sq_dist optional.
  int Nearest(const Vec3& q, double* sq_dist = nullptr) const;
  // Nearest point for every row of Q, in parallel; deterministic and equal to
  // Nearest(q) per row (ties: lowest index). Queries are processed in Morton
  // order, each warm-started from the previous answer.
  void NearestBatch(const MatrixX3d& Q, Eigen::VectorXi* index, VectorXd* sq_dist) const;
  // The k nearest points to q, nearest first (fewer if Size() < k).
  std::vector<int> Knn(const Vec3& q, int k, std::vector<double>* sq_dists = nullptr) const;
  // k nearest neighbours of every row of Q: out is #Q x k (row-major), -1 pads.
  void KnnBatch(const MatrixX3d& Q, int k, Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic,
                                                         Eigen::RowMajor>* out) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace arcs
