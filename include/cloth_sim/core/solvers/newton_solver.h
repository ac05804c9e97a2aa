/// @file newton_solver.h
/// Newton's method on the implicit Euler objective: the accuracy reference.
#pragma once

#include <Eigen/SparseCholesky>

#include "cloth_sim/core/linalg/cholmod_factor.h"
#include "cloth_sim/core/solvers/revision_cache.h"
#include "cloth_sim/core/model/free_particles.h"
#include "cloth_sim/core/solvers/implicit_euler_problem.h"
#include "cloth_sim/core/solvers/solver.h"
#include "cloth_sim/core/linalg/block_pattern.h"

namespace cloth_sim {

/// Minimises g(x) of ImplicitStepProblem by Newton's method: each iteration assembles
/// H = M + h^2 (sum of spring Hessians + soft pin stiffness), solves H dx = -grad g with a
/// sparse Cholesky (pattern analysed once per revision, numeric factorization every iteration),
/// then backtracks (Armijo) along dx.
///
/// Far from the solution the spring Hessians are made positive semi-definite by
/// springHessianBlock (projected Newton: H >= M > 0, so dx is a descent direction). Once a full
/// step is accepted and is small (|dx| < 1e-2 |x - x_0|), the exact Hessian is tried first, and
/// kept while it factors (it is then positive definite, so dx is still a descent direction);
/// this restores quadratic convergence at minima where springs are compressed (buckling
/// cloth), where the projected Hessian converges only linearly (crumpled 6 x 6 test cloth:
/// 75 iterations instead of 112).
///
/// Near machine precision the Armijo test on g fails by round-off; the line search then
/// backtracks on |grad g| instead. Stops when the full step |dx| / |x - x_0| < tolerance (1e-12
/// when the settings give 0), when the gradient vanishes, when no step lowers g or |grad g|,
/// or after max_iterations.
///
/// SolverSettings::linear_solver: kEigen factors with Eigen's SimplicialLLT (the first
/// implementation, kept to compare); the others with CHOLMOD's supernodal factorization
/// (dense blocks through BLAS; docs/benchmark.md, "Performance", has the measured ratio).
class NewtonSolver final : public Solver {
 public:
  const char* name() const override { return "newton"; }
  SolveResult step(const SolverInput& input, const SolverSettings& settings,
                   State& state) override;

  /// Minimises g of @p problem starting from @p x (m; hard-pinned particles at their targets),
  /// in place. step() is minimize from y; the benchmark warm-starts it from a long
  /// local/global run to get converged references cheaply.
  SolveResult minimize(const SolverInput& input, const SolverSettings& settings,
                       const ImplicitStepProblem& problem, Points& x);

 private:
  void prepare(const SolverInput& input, LinearSolver backend);
  /// The Hessian of g: M + h^2 K(x) (@p h the implicit step h_i, s).
  void assembleHessian(const Model& model, const PinSet& pins, const Points& x, double h,
                       bool clamp_psd);
  bool factorize();

  RevisionCache pattern_cache_;  ///< the pattern and its analysis
  LinearSolver backend_ = LinearSolver::kFused;
  FreeParticleMap dofs_;
  BlockPattern pattern_;
  /// Per spring with two free ends: columnStart of blocks (ii, jj, ij, ji) x 3 columns; -1 else.
  std::vector<std::array<int, 12>> spring_slots_;
  /// Per free particle: columnStart of its diagonal block, 3 columns.
  std::vector<std::array<int, 3>> diagonal_slots_;
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>> eigen_;
  CholmodFactor cholmod_{CholmodFactor::Kind::kSupernodal};
};

}  // namespace cloth_sim
