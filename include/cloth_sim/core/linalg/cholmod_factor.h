/// @file cholmod_factor.h
/// Sparse Cholesky factorization by CHOLMOD (SuiteSparse, Chen, Davis, Hager, Rajamanickam 2008,
/// "Algorithm 887: CHOLMOD", ACM TOMS 35(3)). The CHOLMOD headers stay in the .cpp.
#pragma once

#include <memory>
#include <vector>

#include <Eigen/SparseCore>

namespace cloth_sim {

/// A lower-triangular sparse factor L with L L^T = P A P^T: the strictly lower part in CSC with
/// sorted rows, the diagonal apart and inverted.
struct LowerFactor {
  int size = 0;                    ///< n
  /// Column j holds rows col_row[col_start[j] .. col_start[j+1]), increasing.
  std::vector<int> col_start, col_row;
  std::vector<double> col_value;
  std::vector<double> inv_diagonal;  ///< 1 / L_jj
  /// Fill-reducing permutation: row k of P A P^T is row permutation[k] of A.
  std::vector<int> permutation;

  /// Off-diagonal nonzeros.
  long offDiagonalCount() const { return static_cast<long>(col_row.size()); }
};

/// A sparse symmetric positive definite matrix A factored by CHOLMOD.
///
/// The ordering is CHOLMOD's choice among AMD and METIS nested dissection (the one with the
/// fewer nonzeros in L). Simplicial factors suit small factors and exporting L to the fused
/// kernels; supernodal factors (dense blocks through BLAS) suit the large 3N x 3N Newton
/// Hessians, and are much faster with an optimized BLAS (OpenBLAS) than with the reference one.
class CholmodFactor {
 public:
  enum class Kind { kSimplicial, kSupernodal };

  explicit CholmodFactor(Kind kind = Kind::kSimplicial);
  ~CholmodFactor();
  CholmodFactor(const CholmodFactor&) = delete;
  CholmodFactor& operator=(const CholmodFactor&) = delete;
  CholmodFactor(CholmodFactor&&) noexcept;
  CholmodFactor& operator=(CholmodFactor&&) noexcept;

  /// Symbolic analysis of the pattern of @p a (square; only its lower triangle is read).
  void analyze(const Eigen::SparseMatrix<double>& a);
  /// Numeric factorization of @p a (same pattern as analyzed). False if a is not positive
  /// definite (the factor is then unusable until the next successful call).
  bool factorize(const Eigen::SparseMatrix<double>& a);
  /// analyze + factorize.
  bool compute(const Eigen::SparseMatrix<double>& a);

  /// Solves A X = B in place; @p b is column-major, rows x @p columns, leading dimension rows.
  /// Work buffers are kept between calls (no allocation after the first call).
  void solveInPlace(double* b, int columns);

  /// Nonzeros of L (diagonal included), as CHOLMOD counts them.
  double factorNonZeros() const;
  /// The factor as an explicit L (a copy; converts the factor to simplicial L L^T form).
  LowerFactor exportLower();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace cloth_sim
