/// @file local_global_solver.h
/// Liu, Bargteil, O'Brien, Kavan 2013, "Fast Simulation of Mass-Spring Systems", ACM TOG 32(6).
#pragma once

#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCholesky>

#include "cloth_sim/core/dof_map.h"
#include "cloth_sim/core/implicit_euler.h"
#include "cloth_sim/core/solver.h"

namespace cloth_sim {

/// Block coordinate descent on the implicit Euler objective g (METHOD.md):
///  - local step: each spring's direction d_s = r_s (x_i - x_j) / |x_i - x_j|;
///  - global step: (M + h^2 L) x = M y + h^2 (J d + m g + soft-pin and boundary terms).
/// L = L_scalar (x) I3, so ONE scalar N_free x N_free sparse Cholesky factor serves x, y and z
/// (a three-column solve). The factor is kept across steps and recomputed only when the
/// SolverInput revision changes (h, a stiffness, a mass or the pin set). Moving a pin target
/// only changes the right-hand side.
///
/// g never increases from one iterate to the next; the iterates converge (linearly) to the
/// implicit Euler solution that NewtonSolver finds. The initial guess is the inertial prediction y.
class LocalGlobalSolver : public Solver {
 public:
  const char* name() const override { return "local_global"; }
  SolveResult step(const SolverInput& input, const SolverSettings& settings,
                   State& state) override;

  /// Diagnostic hook (tests, benchmark): when set, every step clears it and appends g(x_k) for
  /// the initial guess and every iterate. Costs one spring pass per step. nullptr disables.
  void setObjectiveTrace(std::vector<double>* trace) { trace_ = trace; }

 protected:
  /// Refactors when the revision changed; builds the constant right-hand side of this step.
  void beginStep(const SolverInput& input, const State& state);
  /// One local + global iteration from @p x into @p x_next (hard pins kept at their targets).
  /// Returns g(x), which the local step gets almost for free.
  double iterate(const Points& x, Points& x_next);
  /// g(x) with one spring pass and no solve.
  double objectiveAt(const Points& x) const { return problem_.objective(x); }
  void recordTrace(double g) {
    if (trace_ != nullptr) trace_->push_back(g);
  }
  void clearTrace() {
    if (trace_ != nullptr) trace_->clear();
  }
  bool tracing() const { return trace_ != nullptr; }
  /// Whether this step solves contact forces (SolverInput::contacts was set).
  bool solvesContacts() const { return contacts_ != nullptr; }

  ImplicitStepProblem problem_;

 private:
  void factorize(const SolverInput& input);

  std::uint64_t prepared_revision_ = 0;
  bool prepared_ = false;
  DofMap dofs_;
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>> factor_;
  Points rhs_constant_;            ///< 3 x N: M y + h^2 (m g + k_pin t + k x_boundary)
  ContactForces* contacts_ = nullptr;  ///< this step's contact forces, or nullptr
  Eigen::VectorXd compliance_;     ///< per particle: estimate of (A^-1)_ii (1/kg), 0 if pinned
  Points rhs_;                     ///< 3 x N work buffer
  Eigen::MatrixX3d reduced_rhs_;   ///< N_free x 3
  Eigen::MatrixX3d reduced_x_;     ///< N_free x 3
  std::vector<double>* trace_ = nullptr;
};

/// Local/global with Chebyshev semi-iterative acceleration (Wang 2015, "A Chebyshev
/// Semi-Iterative Approach for Accelerating Projective and Position-based Dynamics"):
///   x_{k+1} = omega_{k+1} (gamma (xhat_{k+1} - x_k) + x_k - x_{k-1}) + x_{k-1},
///   omega = 1 for the first S iterations, 2 / (2 - rho^2) at S, then 4 / (4 - rho^2 omega).
/// Safeguard: when an accelerated iterate raises g, it is replaced by the plain local/global
/// iterate (which never raises g) and the acceleration restarts; the returned iterate is never
/// worse than the last plain local/global one. With rho = 0 in the settings, rho is measured
/// after each refactorization from the contraction rate of plain local/global.
class ChebyshevSolver final : public LocalGlobalSolver {
 public:
  const char* name() const override { return "chebyshev"; }
  SolveResult step(const SolverInput& input, const SolverSettings& settings,
                   State& state) override;
  /// The spectral radius in use (measured or given).
  double rho() const { return rho_; }

 private:
  double calibrateRho(const SolverSettings& settings);

  double rho_ = 0.0;
  std::uint64_t calibrated_revision_ = 0;
  bool calibrated_ = false;
};

}  // namespace cloth_sim
