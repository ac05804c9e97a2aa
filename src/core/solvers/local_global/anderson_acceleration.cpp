#include "cloth_sim/core/solvers/local_global/anderson_acceleration.h"

#include <Eigen/Cholesky>
#include <algorithm>

namespace cloth_sim {

namespace {

/// Doubles per block of the vector loops below (a fixed split: the same sums on any threads).
constexpr std::size_t kGrain = 4096;

}  // namespace

void AndersonAcceleration::begin(const SolverInput&, const SolverSettings& settings) {
  window_ = settings.params.integer(settings::kAndersonWindow);
  threads_ = resolveThreads(settings.threads);
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
  const BlockSplit split(static_cast<std::size_t>(n), kGrain);
  if (has_last_) {
    // The least-squares problem does not depend on the column order: overwrite the oldest.
    const int c = next_column_;
    history_ = std::min(history_ + 1, window_);
    next_column_ = (c + 1) % window_;
    // The new column, and its dot products with the columns in use, per block.
    std::vector<double> partial(static_cast<std::size_t>(split.blocks()) * history_, 0.0);
    double* df = d_f_.data() + c * n;
    double* dg = d_g_.data() + c * n;
    parallelFor(threads_, split.blocks(), [&](int b) {
      for (std::size_t i = split.begin(b); i < split.end(b); ++i) {
        df[i] = f[i] - f_last_[i];
        dg[i] = g_map[i] - g_last_[i];
        f_last_[i] = f[i];
        g_last_[i] = g_map[i];
      }
      for (int j = 0; j < history_; ++j) {
        const double* dj = d_f_.data() + j * n;
        double sum = 0.0;
        for (std::size_t i = split.begin(b); i < split.end(b); ++i) sum += df[i] * dj[i];
        partial[static_cast<std::size_t>(b) * history_ + j] = sum;
      }
    });
    for (int j = 0; j < history_; ++j) {
      double sum = 0.0;
      for (int b = 0; b < split.blocks(); ++b) sum += partial[static_cast<std::size_t>(b) * history_ + j];
      gram_(c, j) = gram_(j, c) = sum;
    }
  } else {
    f_last_.resize(f.size());
    g_last_.resize(g_map.size());
    parallelFor(threads_, split.blocks(), [&](int b) {
      for (std::size_t i = split.begin(b); i < split.end(b); ++i) {
        f_last_[i] = f[i];
        g_last_[i] = g_map[i];
      }
    });
  }
  has_last_ = true;
}

bool AndersonAcceleration::extrapolate(const NodeBuffer&, const NodeBuffer& x,
                                       const NodeBuffer& x_hat, NodeBuffer& x_next) {
  const std::size_t n = x.size();
  const BlockSplit split(n, kGrain);
  f_.resize(n);
  parallelFor(threads_, split.blocks(), [&](int b) {
    for (std::size_t i = split.begin(b); i < split.end(b); ++i) f_[i] = x_hat[i] - x[i];
  });
  pushHistory(f_, x_hat);
  if (history_ == 0) return false;
  // Normal equations (dF^T dF) theta = dF^T F (dF^T dF kept up to date column by column), with
  // a tiny Tikhonov term against nearly collinear columns.
  std::vector<double> partial(static_cast<std::size_t>(split.blocks()) * history_, 0.0);
  parallelFor(threads_, split.blocks(), [&](int b) {
    for (int j = 0; j < history_; ++j) {
      const double* dj = d_f_.data() + j * static_cast<Eigen::Index>(n);
      double sum = 0.0;
      for (std::size_t i = split.begin(b); i < split.end(b); ++i) sum += dj[i] * f_[i];
      partial[static_cast<std::size_t>(b) * history_ + j] = sum;
    }
  });
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(history_);
  for (int b = 0; b < split.blocks(); ++b)
    for (int j = 0; j < history_; ++j) rhs[j] += partial[static_cast<std::size_t>(b) * history_ + j];
  Eigen::MatrixXd gram = gram_.topLeftCorner(history_, history_);
  gram.diagonal().array() += 1e-12 * std::max(gram.diagonal().maxCoeff(), 1e-300);
  Eigen::VectorXd theta = gram.ldlt().solve(rhs);
  if (!theta.allFinite()) theta.setZero();
  x_next.resize(n);
  parallelFor(threads_, split.blocks(), [&](int b) {
    for (std::size_t i = split.begin(b); i < split.end(b); ++i) {
      double v = x_hat[i];
      for (int j = 0; j < history_; ++j) v -= d_g_(static_cast<Eigen::Index>(i), j) * theta[j];
      x_next[i] = v;
    }
  });
  return true;  // even unchanged: it is checked like an extrapolation
}

}  // namespace cloth_sim
