#include "cloth_sim/core/solvers/local_global/lbfgs_solver.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace cloth_sim {
namespace {

/// Armijo's sufficient-decrease constant c1 (Nocedal and Wright, sec. 3.1).
constexpr double kArmijo = 1e-4;
/// Halvings of the step length before the line search gives up.
constexpr int kMaxHalvings = 5;
/// A pair is kept when s.t > kCurvature |s| |t|.
constexpr double kCurvature = 1e-12;

/// The first @p n doubles of @p v (the free nodes).
Eigen::Map<Eigen::VectorXd> head(NodeBuffer& v, Eigen::Index n) {
  return Eigen::Map<Eigen::VectorXd>(v.data(), n);
}
Eigen::Map<const Eigen::VectorXd> head(const NodeBuffer& v, Eigen::Index n) {
  return Eigen::Map<const Eigen::VectorXd>(v.data(), n);
}

}  // namespace

void LbfgsSolver::evaluate(Point& at) { at.g = problem_.objectiveAndGradient(at.x, at.gradient); }

void LbfgsSolver::clearHistory() {
  history_ = 0;
  newest_ = -1;
}

void LbfgsSolver::direction(const NodeBuffer& gradient, NodeBuffer& p) {
  const Eigen::Index n = static_cast<Eigen::Index>(kNodeStride) * problem_.freeNodeCount();
  const int window = static_cast<int>(s_.cols());
  p.assign(gradient.size(), 0.0);
  auto q = head(p, n);
  q = head(gradient, n);
  alpha_.assign(history_, 0.0);
  for (int i = 0; i < history_; ++i) {  // newest first
    const int c = (newest_ - i + window) % window;
    alpha_[i] = inverse_st_[c] * s_.col(c).dot(q);
    q.noalias() -= alpha_[i] * t_.col(c);
  }
  problem_.solveGlobal(p);  // r = H0 q = A^-1 q
  for (int i = history_ - 1; i >= 0; --i) {  // oldest first
    const int c = (newest_ - i + window) % window;
    const double beta = inverse_st_[c] * t_.col(c).dot(q);
    q.noalias() += (alpha_[i] - beta) * s_.col(c);
  }
  q = -q;
}

bool LbfgsSolver::lineSearch(const Point& from, const NodeBuffer& p, Point& trial) {
  const Eigen::Index n = static_cast<Eigen::Index>(kNodeStride) * problem_.freeNodeCount();
  const double slope = head(from.gradient, n).dot(head(p, n));  // grad.p
  if (!(slope < 0.0)) return false;  // not a descent direction (or not finite)
  trial.x = from.x;  // hard-pinned rows stay
  double a = 1.0;
  for (int halving = 0; halving <= kMaxHalvings; ++halving, a *= 0.5) {
    head(trial.x, n) = head(from.x, n) + a * head(p, n);
    evaluate(trial);
    if (trial.g <= from.g + kArmijo * a * slope) return true;
  }
  return false;
}

void LbfgsSolver::pushPair(const Point& from, const Point& to, int window) {
  const Eigen::Index n = static_cast<Eigen::Index>(kNodeStride) * problem_.freeNodeCount();
  if (s_.rows() != n || s_.cols() != window) {
    s_.resize(n, window);
    t_.resize(n, window);
    inverse_st_.assign(window, 0.0);
    clearHistory();
  }
  const int c = (newest_ + 1) % window;
  s_.col(c) = head(to.x, n) - head(from.x, n);
  t_.col(c) = head(to.gradient, n) - head(from.gradient, n);
  const double st = s_.col(c).dot(t_.col(c));
  if (!(st > kCurvature * s_.col(c).norm() * t_.col(c).norm())) {
    ++skipped_pairs_;  // column c is not in use (or is the oldest, now dropped)
    if (history_ == window) --history_;
    return;
  }
  inverse_st_[c] = 1.0 / st;
  newest_ = c;
  history_ = std::min(history_ + 1, window);
}

SolveResult LbfgsSolver::step(const SolverInput& in, const SolverSettings& settings,
                              State& state) {
  const SolverInput without_contacts{in.model, in.pins, in.h, in.revision, nullptr};
  factorizations_ += problem_.begin(without_contacts, settings, state);
  hooks_.clearTrace();
  clearHistory();
  const NodeBuffer start = problem_.initialGuess(settings);
  Point x, next;
  x.x = start;
  evaluate(x);
  hooks_.record(x.g);
  NodeBuffer p;
  int solves = 0;
  IterationError error;
  SolveResult result;
  while (solves < settings.max_iterations) {
    direction(x.gradient, p);
    ++solves;
    if (history_ == 0) {
      // p = -A^-1 grad: the local/global iterate, which never raises g. No line search.
      next.x = x.x;
      head(next.x, static_cast<Eigen::Index>(kNodeStride) * problem_.freeNodeCount()) +=
          head(p, static_cast<Eigen::Index>(kNodeStride) * problem_.freeNodeCount());
      evaluate(next);
    } else if (!lineSearch(x, p, next)) {
      ++fallbacks_;
      clearHistory();
      if (solves >= settings.max_iterations) {
        hooks_.observe(solves, x.x, problem_);  // the step ends on x
        break;
      }
      continue;  // the next direction is the plain local/global one
    }
    pushPair(x, next, settings.params.integer(settings::kLbfgsWindow));
    result.iterations = solves;
    result.convergence = relativeChange(next.x, x.x, start);
    const double change = problem_.rmsDistance(next.x, x.x);
    std::swap(x, next);
    hooks_.record(x.g);
    if (!hooks_.observe(solves, x.x, problem_)) break;
    if (in.iteration_tolerance > 0.0 && error.add(change) <= in.iteration_tolerance) {
      result.converged = true;
      break;
    }
    if (settings.tolerance > 0.0 && result.convergence < settings.tolerance) {
      result.converged = true;
      break;
    }
    if (solves < settings.max_iterations && in.pastDeadline(solves)) {
      result.cut = true;
      break;
    }
  }
  result.iterations = solves;
  if (in.iteration_tolerance > 0.0) result.iteration_error = error.estimate();
  problem_.finishStep(x.x, state);
  result.used_contacts = false;  // contacts are not solved here (see the class comment)
  return result;
}

}  // namespace cloth_sim
