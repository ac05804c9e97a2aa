#include "cloth_sim/core/solvers/local_global/anderson_acceleration.h"

#include <Eigen/Cholesky>
#include <algorithm>

namespace cloth_sim {

void AndersonAcceleration::begin(const SolverInput&, const SolverSettings& settings) {
  window_ = settings.params.integer(settings::kAndersonWindow);
  clearHistory();
}

void AndersonAcceleration::restart() {
  ++restarts_;
  clearHistory();
}

void AndersonAcceleration::clearHistory() {
  history_ = 0;
  next_column_ = 0;  // columns 0 .. history_ - 1 are the ones in use until the ring is full
  has_last_ = false;
}

void AndersonAcceleration::pushHistory(const NodeBuffer& f, const NodeBuffer& g_map) {
  const Eigen::Index n = static_cast<Eigen::Index>(f.size());
  if (d_f_.rows() != n || d_f_.cols() != window_) {
    d_f_.resize(n, window_);
    d_g_.resize(n, window_);
    gram_.setZero(window_, window_);
    history_ = 0;
    next_column_ = 0;
  }
  if (has_last_) {
    // The least-squares problem does not depend on the column order: overwrite the oldest.
    const int c = next_column_;
    d_f_.col(c) = asVector(f) - asVector(f_last_);
    d_g_.col(c) = asVector(g_map) - asVector(g_last_);
    history_ = std::min(history_ + 1, window_);
    next_column_ = (c + 1) % window_;
    for (int j = 0; j < history_; ++j) gram_(c, j) = gram_(j, c) = d_f_.col(c).dot(d_f_.col(j));
  }
  f_last_ = f;
  g_last_ = g_map;
  has_last_ = true;
}

bool AndersonAcceleration::extrapolate(const NodeBuffer&, const NodeBuffer& x,
                                       const NodeBuffer& x_hat, NodeBuffer& x_next) {
  f_.resize(x.size());
  asVector(f_) = asVector(x_hat) - asVector(x);
  pushHistory(f_, x_hat);
  if (history_ == 0) return false;
  asVector(x_next) = asVector(x_hat);
  // Normal equations (dF^T dF) theta = dF^T F (dF^T dF kept up to date column by column), with
  // a tiny Tikhonov term against nearly collinear columns.
  Eigen::MatrixXd gram = gram_.topLeftCorner(history_, history_);
  const Eigen::VectorXd rhs = d_f_.leftCols(history_).transpose() * asVector(f_);
  gram.diagonal().array() += 1e-12 * std::max(gram.diagonal().maxCoeff(), 1e-300);
  const Eigen::VectorXd theta = gram.ldlt().solve(rhs);
  if (theta.allFinite()) asVector(x_next).noalias() -= d_g_.leftCols(history_) * theta;
  return true;  // even unchanged: it is checked like an extrapolation
}

}  // namespace cloth_sim
