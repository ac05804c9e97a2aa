/// @file block_pattern.h
/// A symmetric block-sparse matrix whose pattern is fixed once, so numeric values are written in
/// place at every assembly (no triplet sort per Newton iteration).
#pragma once

#include <utility>
#include <vector>

#include <Eigen/SparseCore>

namespace cloth_sim {

/// Pattern of a (nodes*block) square matrix with dense block x block blocks on the diagonal and
/// at (i, j), (j, i) for every listed pair. Column-major (CSC) as Eigen's Cholesky wants.
class BlockPattern {
 public:
  BlockPattern() = default;
  BlockPattern(int nodes, int block, const std::vector<std::pair<int, int>>& pairs);

  /// Index into matrix().valuePtr() of entry (block row i, block column j, column b of the
  /// block, row 0 of the block); rows a = 0..block-1 of that column follow contiguously.
  int columnStart(int i, int j, int b) const;

  Eigen::SparseMatrix<double>& matrix() { return matrix_; }
  const Eigen::SparseMatrix<double>& matrix() const { return matrix_; }
  int block() const { return block_; }

 private:
  Eigen::SparseMatrix<double> matrix_;
  int block_ = 1;
};

}  // namespace cloth_sim
