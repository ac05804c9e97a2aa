#include "cloth_sim/core/scalar_system.h"

#include <numeric>
#include <stdexcept>

#include "cloth_sim/core/triangular_kernels.h"

namespace cloth_sim {

void ScalarSystem::factor(const Eigen::SparseMatrix<double>& a, LinearSolver backend) {
  backend_ = backend;
  const int n = static_cast<int>(a.rows());
  order_.resize(n);
  std::iota(order_.begin(), order_.end(), 0);
  lower_ = LowerFactor{};
  bool ok = true;
  if (backend == LinearSolver::kEigen) {
    eigen_.compute(a);
    ok = eigen_.info() == Eigen::Success;
    if (ok) factor_nonzeros_ = Eigen::SparseMatrix<double>(eigen_.matrixL()).nonZeros();
  } else {
    ok = cholmod_.compute(a);
    factor_nonzeros_ = static_cast<long>(cholmod_.factorNonZeros());
    if (ok && backend == LinearSolver::kFused) {
      lower_ = cholmod_.exportLower();
      order_ = lower_.permutation;
    }
  }
  if (!ok) throw std::runtime_error("global step matrix is not positive definite");
  columns_.resize(n, 3);
  solution_.resize(n, 3);
}

void ScalarSystem::solveInPlace(double* x) {
  const int n = size();
  if (n == 0) return;
  if (backend_ == LinearSolver::kFused) {
    solveFused3(lower_, x);
    return;
  }
  for (int k = 0; k < n; ++k)
    for (int c = 0; c < 3; ++c) columns_(k, c) = x[kNodeStride * k + c];
  if (backend_ == LinearSolver::kEigen) {
    solution_ = eigen_.solve(columns_);
  } else {
    cholmod_.solveInPlace(columns_.data(), 3);
    solution_.swap(columns_);
  }
  for (int k = 0; k < n; ++k)
    for (int c = 0; c < 3; ++c) x[kNodeStride * k + c] = solution_(k, c);
}

}  // namespace cloth_sim
