/// @file lbfgs_solver.h
/// Liu, Bouaziz, Kavan 2017, "Quasi-Newton Methods for Real-Time Simulation of Hyperelastic
/// Materials", ACM TOG 36(3): L-BFGS on the implicit Euler objective g, with the local/global
/// matrix as the initial Hessian.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "cloth_sim/core/solvers/local_global/local_global_solver.h"

namespace cloth_sim {

namespace settings {
/// lbfgs: number m of (s, t) pairs kept by L-BFGS (Liu, Bouaziz, Kavan 2017 use 5).
inline constexpr SolverParam kLbfgsWindow{{"solver.lbfgs.window", "", Range::closed(1, 50), true,
                                           "", "", "(s, t) pairs kept by L-BFGS", 0},
                                          5};
}  // namespace settings

/// L-BFGS on g(x) = 1/2 (x - y)^T M (x - y) + h^2 E(x) - h^2 x^T f_ext (docs/method.md) with the
/// initial inverse Hessian H0 = A^-1, A = M + h^2 L the prefactored local/global matrix
/// (Liu, Bouaziz, Kavan 2017, sec. 4 and Algorithm 1). Per iteration:
///  - gradient grad g(x) = A x - b(x) (LocalGlobalProblem::objectiveAndGradient: one spring pass and one product
///    with A; it comes with the energy of the previous line-search point);
///  - two-loop recursion over the last m pairs s_i = x_{i+1} - x_i, t_i = grad_{i+1} - grad_i
///    (m = settings::kLbfgsWindow): q = grad; alpha_i = s_i.q / s_i.t_i, q -= alpha_i t_i
///    (newest first); r = A^-1 q (ONE solve); beta_i = t_i.r / s_i.t_i, r += (alpha_i - beta_i) s_i
///    (oldest first); direction p = -r;
///  - Armijo backtracking g(x + a p) <= g(x) + 1e-4 a grad.p from a = 1, halving at most 5
///    times. If it still fails, the plain local/global iterate x - A^-1 grad replaces it (one
///    more solve) and the history is cleared.
/// With an empty history p = -A^-1 grad, so x + p is exactly the local/global iterate (which
/// never raises g: it minimises a quadratic upper bound of g), and iteration 1 equals
/// local/global. A pair is kept only when s.t > 1e-12 |s| |t|, so the implied Hessian stays
/// positive definite on this non-convex g. The accepted iterates never raise g.
///
/// Every solve counts as an iteration (SolverSettings::max_iterations). Hard-pinned nodes stay
/// at their targets (all vectors cover the free nodes only); soft pins are part of A and b.
/// Contact forces (SolverInput::contacts) are not solved: SolveResult::used_contacts stays
/// false and the simulation projects contacts after the step instead.
class LbfgsSolver final : public LocalGlobalFamily {
 public:
  const char* name() const override { return "lbfgs"; }
  SolveResult step(const SolverInput& input, const SolverSettings& settings,
                   State& state) override;
  /// Line searches that failed and fell back to the plain local/global iterate (diagnostics).
  int fallbacks() const { return fallbacks_; }
  /// Pairs (s, t) refused by the curvature test s.t > 1e-12 |s| |t| (diagnostics).
  int skippedPairs() const { return skipped_pairs_; }

 private:
  /// A point x with g(x) and grad g(x).
  struct Point {
    NodeBuffer x, gradient;
    double g = 0.0;
  };
  /// Sets @p at.g and @p at.gradient from @p at.x.
  void evaluate(Point& at);
  /// p = -H grad by the two-loop recursion (one solve). Empty history: p = -A^-1 grad.
  void direction(const NodeBuffer& gradient, NodeBuffer& p);
  /// Armijo backtracking along @p p from @p from into @p trial; false if every step failed.
  bool lineSearch(const Point& from, const NodeBuffer& p, Point& trial);
  /// Keeps s = to.x - from.x, t = to.gradient - from.gradient if s.t > 1e-12 |s| |t|.
  void pushPair(const Point& from, const Point& to, int window);
  void clearHistory();

  Eigen::MatrixXd s_, t_;          ///< columns: the last pairs (a ring)
  std::vector<double> inverse_st_;  ///< 1 / s_i.t_i per column
  std::vector<double> alpha_;       ///< two-loop work
  int history_ = 0;                 ///< columns in use
  int newest_ = -1;                 ///< the ring's newest column
  int fallbacks_ = 0;
  int skipped_pairs_ = 0;
};

}  // namespace cloth_sim
