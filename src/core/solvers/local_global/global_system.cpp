#include "cloth_sim/core/solvers/local_global/global_system.h"

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <utility>

#include "cloth_sim/core/solvers/local_global/local_step.h"


namespace cloth_sim {

void GlobalSystem::factor(const Eigen::SparseMatrix<double>& a, LinearSolver backend) {
  backend_ = backend;
  const int n = static_cast<int>(a.rows());
  order_.resize(n);
  std::iota(order_.begin(), order_.end(), 0);
  supernodal_ = SupernodalFactor{};
  single_ = SupernodalFactorF{};
  row_begin_.clear();
  columns_.resize(n, 3);
  solution_.resize(n, 3);
  factor_nonzeros_ = 0;
  if (n == 0) return;  // everything pinned: nothing to solve
  bool ok = true;
  if (backend == LinearSolver::kEigen) {
    eigen_.compute(a);
    ok = eigen_.info() == Eigen::Success;
    if (ok) factor_nonzeros_ = Eigen::SparseMatrix<double>(eigen_.matrixL()).nonZeros();
  } else {
    ok = cholmod_.compute(a);
    factor_nonzeros_ = static_cast<long>(cholmod_.factorNonZeros());
    if (ok && (backend == LinearSolver::kFused || backend == LinearSolver::kFusedFloat)) {
      supernodal_ = makeSupernodal(cholmod_.exportLower());
      splitSolves(supernodal_);  // the fixed split the threads share (a function of A only)
      order_ = supernodal_.permutation;
    }
    if (ok && backend == LinearSolver::kFusedFloat) {
      single_ = toSinglePrecision(supernodal_);
      single_work_.assign(static_cast<std::size_t>(kNodeStride) * n, 0.0f);
      keepNodeMatrix(a);
    }
  }
  if (!ok) throw std::runtime_error("global step matrix is not positive definite");
}

void GlobalSystem::keepNodeMatrix(const Eigen::SparseMatrix<double>& a) {
  // Row k in node order is column order_[k] of the symmetric a; its entries by node.
  const int n = size();
  std::vector<int> node_of(n);
  for (int k = 0; k < n; ++k) node_of[order_[k]] = k;
  row_begin_.assign(1, 0);
  column_.clear();
  value_.clear();
  std::vector<std::pair<int, double>> row;
  for (int k = 0; k < n; ++k) {
    row.clear();
    for (Eigen::SparseMatrix<double>::InnerIterator it(a, order_[k]); it; ++it) {
      row.emplace_back(node_of[it.row()], it.value());
    }
    std::sort(row.begin(), row.end());
    for (const auto& [column, value] : row) {
      column_.push_back(column);
      value_.push_back(value);
    }
    row_begin_.push_back(static_cast<int>(column_.size()));
  }
}

void GlobalSystem::globalStep(const double* x, double* b) {
  const int n = size();
  if (backend_ != LinearSolver::kFusedFloat || n == 0) return solveInPlace(b);
  const BlockSplit split(static_cast<std::size_t>(n), kNodeGrain);
  float* r = single_work_.data();
  parallelFor(threads_, split.blocks(), [&](int block) {  // r = b - A x, rounded to float
    for (std::size_t k = split.begin(block); k < split.end(block); ++k) {
      double ax[3] = {0.0, 0.0, 0.0};
      for (int e = row_begin_[k]; e < row_begin_[k + 1]; ++e) {
        const double* xj = x + kNodeStride * column_[e];
        for (int c = 0; c < 3; ++c) ax[c] += value_[e] * xj[c];
      }
      for (int c = 0; c < 3; ++c) r[kNodeStride * k + c] = static_cast<float>(b[kNodeStride * k + c] - ax[c]);
    }
  });
  solveFused3(single_, r, threads_);
  parallelFor(threads_, split.blocks(), [&](int block) {  // x + the correction
    for (std::size_t k = split.begin(block); k < split.end(block); ++k) {
      for (int c = 0; c < 3; ++c) {
        b[kNodeStride * k + c] = x[kNodeStride * k + c] + static_cast<double>(r[kNodeStride * k + c]);
      }
    }
  });
}

void GlobalSystem::solveInPlace(double* x) {
  const int n = size();
  if (n == 0) return;
  if (backend_ == LinearSolver::kFused) {
    solveFused3(supernodal_, x, threads_);
    return;
  }
  if (backend_ == LinearSolver::kFusedFloat) {
    float* r = single_work_.data();
    for (std::size_t k = 0; k < single_work_.size(); ++k) r[k] = static_cast<float>(x[k]);
    solveFused3(single_, r, threads_);
    for (std::size_t k = 0; k < single_work_.size(); ++k) x[k] = static_cast<double>(r[k]);
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

Eigen::SparseMatrix<double> globalStepMatrix(const Model& model, const PinSet& pins,
                                             const FreeParticleMap& dofs, double h) {
  const Springs& springs = model.springs;
  const double h2 = h * h;
  const int nf = dofs.freeCount();
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(nf + 4 * springs.size() + pins.size());
  for (int f = 0; f < nf; ++f) entries.emplace_back(f, f, model.mass[dofs.free_particles[f]]);
  for (const Pin& pin : pins.pins()) {
    if (pin.isHard()) continue;
    const int f = dofs.reduced_index[pin.vertex];
    entries.emplace_back(f, f, h2 * pin.stiffness);
  }
  for (std::size_t s = 0; s < springs.size(); ++s) {
    const int i = dofs.reduced_index[springs.first[s]], j = dofs.reduced_index[springs.second[s]];
    const double k = h2 * springs.stiffness[s];
    if (i >= 0) entries.emplace_back(i, i, k);
    if (j >= 0) entries.emplace_back(j, j, k);
    if (i >= 0 && j >= 0) {
      entries.emplace_back(i, j, -k);
      entries.emplace_back(j, i, -k);
    }
  }
  Eigen::SparseMatrix<double> a(nf, nf);
  a.setFromTriplets(entries.begin(), entries.end());
  a.makeCompressed();
  return a;
}

Points globalStepConstant(const Model& model, const PinSet& pins, const FreeParticleMap& dofs,
                          double h, const Points& y) {
  const double h2 = h * h;
  Points rhs = (y + h2 * model.gravity.replicate(1, y.cols())) * model.mass.asDiagonal();
  for (const Pin& pin : pins.pins()) {
    if (!pin.isHard()) rhs.col(pin.vertex) += h2 * pin.stiffness * pin.target;
  }
  const Springs& springs = model.springs;
  for (std::size_t s = 0; s < springs.size(); ++s) {
    const int i = springs.first[s], j = springs.second[s];
    const bool free_i = dofs.isFree(i), free_j = dofs.isFree(j);
    if (free_i == free_j) continue;
    const double k = h2 * springs.stiffness[s];
    if (free_i) rhs.col(i) += k * y.col(j);
    else rhs.col(j) += k * y.col(i);
  }
  return rhs;
}

}  // namespace cloth_sim
