/// @file newton_solver.h
/// Newton's method on the implicit Euler objective: the accuracy reference.
#pragma once

#include <Eigen/SparseCholesky>

#include "cloth_sim/core/dof_map.h"
#include "cloth_sim/core/solver.h"
#include "cloth_sim/core/sparse_pattern.h"

namespace cloth_sim {

/// Minimises g(x) of ImplicitStepProblem by Newton's method: each iteration assembles
/// H = M + h^2 (sum of spring Hessians made PSD by springHessianBlock + soft pin stiffness),
/// solves H dx = -grad g with a sparse Cholesky (pattern analysed once per revision, numeric
/// factorization every iteration), then backtracks (Armijo) along dx. Since H >= M > 0, dx is a
/// descent direction and g decreases at every iteration.
///
/// Stops when the relative update |dx| / |x - x_0| < tolerance (1e-12 when the settings give 0),
/// when the gradient vanishes, when the line search cannot decrease g any more (machine
/// precision), or after max_iterations.
class NewtonSolver final : public Solver {
 public:
  const char* name() const override { return "newton"; }
  SolveResult step(const SolverInput& input, const SolverSettings& settings,
                   State& state) override;

 private:
  void prepare(const SolverInput& input);
  void assembleHessian(const Model& model, const PinSet& pins, const Points& x);

  std::uint64_t prepared_revision_ = 0;
  bool prepared_ = false;
  DofMap dofs_;
  BlockPattern pattern_;
  /// Per spring with two free ends: columnStart of blocks (ii, jj, ij, ji) x 3 columns; -1 else.
  std::vector<std::array<int, 12>> spring_slots_;
  /// Per free particle: columnStart of its diagonal block, 3 columns.
  std::vector<std::array<int, 3>> diagonal_slots_;
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>> factor_;
};

}  // namespace cloth_sim
