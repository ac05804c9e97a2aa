#include "cloth_sim/core/solvers/local_global/anderson_acceleration.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <utility>

namespace cloth_sim {

namespace {

/// Doubles per block of the vector loops below (a fixed split: the same sums on any threads).
constexpr std::size_t kGrain = 4096;

using TwoDots = std::pair<double, double>;

/// (a . b, a . c) over [begin, end): four interleaved sums each, so the additions do not wait
/// on one another (one chain of dependent additions is latency-bound). The order of the
/// additions depends on the range only: the same sums on any threads.
TwoDots twoDots(const double* a, const double* b, const double* c, std::size_t begin,
                std::size_t end) {
  double ab[4] = {0.0, 0.0, 0.0, 0.0}, ac[4] = {0.0, 0.0, 0.0, 0.0};
  std::size_t i = begin;
  for (; i + 4 <= end; i += 4) {
    for (int k = 0; k < 4; ++k) {
      ab[k] += a[i + k] * b[i + k];
      ac[k] += a[i + k] * c[i + k];
    }
  }
  for (; i < end; ++i) {
    ab[0] += a[i] * b[i];
    ac[0] += a[i] * c[i];
  }
  return {(ab[0] + ab[1]) + (ab[2] + ab[3]), (ac[0] + ac[1]) + (ac[2] + ac[3])};
}

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

bool AndersonAcceleration::extrapolate(const NodeBuffer&, const NodeBuffer& x,
                                       const NodeBuffer& x_hat, NodeBuffer& x_next) {
  const std::size_t n = x.size();
  const Eigen::Index rows = static_cast<Eigen::Index>(n);
  if (d_f_.rows() != rows || d_f_.cols() != window_) {
    d_f_.resize(rows, window_);
    d_g_.resize(rows, window_);
    gram_.setZero(window_, window_);
    clearHistory();
  }
  const BlockSplit split(n, kGrain);
  if (!has_last_) {
    f_last_.resize(n);
    g_last_.resize(n);
    parallelFor(threads_, split.blocks(), [&](int b) {
      for (std::size_t i = split.begin(b); i < split.end(b); ++i) {
        f_last_[i] = x_hat[i] - x[i];
        g_last_[i] = x_hat[i];
      }
    });
    has_last_ = true;
    return false;
  }
  // The least-squares problem does not depend on the column order: overwrite the oldest.
  const int c = next_column_;
  history_ = std::min(history_ + 1, window_);
  next_column_ = (c + 1) % window_;
  const int h = history_;
  // One pass over the vectors (they are memory-bound): F = G(x) - x, the new columns dF, dG,
  // and per block the new column's dot products with the columns in use (dF^T dF, kept up to
  // date column by column) and every column's dot product with F (the normal equations' right
  // side). The block's new column is still in cache for the dot products.
  std::vector<double> partial(static_cast<std::size_t>(split.blocks()) * 2 * h, 0.0);
  double* df = d_f_.data() + c * rows;
  double* dg = d_g_.data() + c * rows;
  parallelFor(threads_, split.blocks(), [&](int b) {
    const std::size_t begin = split.begin(b), end = split.end(b);
    for (std::size_t i = begin; i < end; ++i) {
      const double f = x_hat[i] - x[i];
      df[i] = f - f_last_[i];
      dg[i] = x_hat[i] - g_last_[i];
      f_last_[i] = f;
      g_last_[i] = x_hat[i];
    }
    double* out = &partial[static_cast<std::size_t>(b) * 2 * h];
    for (int j = 0; j < h; ++j) {
      const TwoDots sums = twoDots(d_f_.data() + j * rows, df, f_last_.data(), begin, end);
      out[2 * j] = sums.first;
      out[2 * j + 1] = sums.second;
    }
  });
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(h);
  for (int j = 0; j < h; ++j) {
    double gram_sum = 0.0;
    for (int b = 0; b < split.blocks(); ++b) {
      gram_sum += partial[static_cast<std::size_t>(b) * 2 * h + 2 * j];
      rhs[j] += partial[static_cast<std::size_t>(b) * 2 * h + 2 * j + 1];
    }
    gram_(c, j) = gram_(j, c) = gram_sum;
  }
  // Normal equations (dF^T dF) theta = dF^T F, with a tiny Tikhonov term against nearly
  // collinear columns.
  Eigen::MatrixXd gram = gram_.topLeftCorner(h, h);
  gram.diagonal().array() += 1e-12 * std::max(gram.diagonal().maxCoeff(), 1e-300);
  Eigen::VectorXd theta = gram.ldlt().solve(rhs);
  if (!theta.allFinite()) theta.setZero();
  x_next.resize(n);
  parallelFor(threads_, split.blocks(), [&](int b) {
    const std::size_t begin = split.begin(b), end = split.end(b);
    // Column by column over the block (contiguous, vectorized); the block stays in cache.
    std::copy(x_hat.begin() + begin, x_hat.begin() + end, x_next.begin() + begin);
    for (int j = 0; j < h; ++j) {
      const double* dgj = d_g_.data() + j * rows;
      const double t = theta[j];
      for (std::size_t i = begin; i < end; ++i) x_next[i] -= dgj[i] * t;
    }
  });
  return true;  // even unchanged: it is checked like an extrapolation
}

}  // namespace cloth_sim
