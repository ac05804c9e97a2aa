/// @file local_global_solver.h
/// Liu, Bargteil, O'Brien, Kavan 2013, "Fast Simulation of Mass-Spring Systems", ACM TOG 32(6),
/// and its accelerated variants.
#pragma once

#include <vector>

#include "cloth_sim/core/solvers/local_global/anderson_acceleration.h"
#include "cloth_sim/core/solvers/local_global/chebyshev_acceleration.h"
#include "cloth_sim/core/solvers/local_global/iteration_hooks.h"
#include "cloth_sim/core/solvers/local_global/local_global_driver.h"
#include "cloth_sim/core/solvers/local_global/local_global_problem.h"
#include "cloth_sim/core/solvers/solver.h"

namespace cloth_sim {

/// What the local/global family (local_global, chebyshev, anderson, lbfgs) shares: the
/// LocalGlobalProblem it holds and the diagnostic hooks of tests and benchmark.
class LocalGlobalFamily : public Solver {
 public:
  /// See IterationHooks::setObjectiveTrace.
  void setObjectiveTrace(std::vector<double>* trace) { hooks_.setObjectiveTrace(trace); }
  /// See IterationHooks::setIterateObserver.
  void setIterateObserver(IterateObserver observer) { hooks_.setIterateObserver(std::move(observer)); }
  /// The global step's factored system (valid after the first step).
  const GlobalSystem& system() const { return problem_.system(); }
  /// The springs as the local step sees them (valid after the first step).
  const SpringTable& springTable() const { return problem_.springTable(); }
  /// The problem's warm start (LocalGlobalProblem::warmStart).
  SolverCarry carriedOver() const override { return problem_.warmStart(); }
  void carryOver(const SolverCarry& carry) override { problem_.setWarmStart(carry); }

 protected:
  LocalGlobalProblem problem_;
  IterationHooks hooks_;
  LocalGlobalIterates iterates_;  ///< runLocalGlobal's buffers
};

/// Block coordinate descent on the implicit Euler objective g (LocalGlobalProblem,
/// docs/method.md): exactly SolverSettings::max_iterations local/global iterations per step,
/// unless the tolerance stops them first (runLocalGlobal). g never increases from one iterate
/// to the next; the iterates converge (linearly) to the implicit Euler solution that
/// NewtonSolver finds. The initial guess is the inertial prediction y (or the warm start).
/// Contact forces (SolverInput::contacts) are solved with the step.
class LocalGlobalSolver : public LocalGlobalFamily {
 public:
  LocalGlobalSolver() = default;
  LocalGlobalSolver(const LocalGlobalSolver&) = delete;
  LocalGlobalSolver& operator=(const LocalGlobalSolver&) = delete;

  const char* name() const override { return "local_global"; }
  SolveResult step(const SolverInput& input, const SolverSettings& settings,
                   State& state) override;

 protected:
  /// The same iterations, extrapolated by @p acceleration (owned by the derived solver).
  explicit LocalGlobalSolver(Acceleration* acceleration) : acceleration_(acceleration) {}

 private:
  Acceleration* acceleration_ = nullptr;  ///< nullptr: plain local/global
};

/// Local/global with Chebyshev semi-iterative acceleration (ChebyshevAcceleration, Wang 2015)
/// and the driver's energy safeguard: the returned iterate is never worse than the last plain
/// local/global one. Solves contact forces like local_global.
class ChebyshevSolver final : public LocalGlobalSolver {
 public:
  ChebyshevSolver() : LocalGlobalSolver(&chebyshev_) {}
  const char* name() const override { return "chebyshev"; }
  /// The spectral radius in use (given or the bound localGlobalRhoBound).
  double rho() const { return chebyshev_.rho(); }

 private:
  ChebyshevAcceleration chebyshev_;
};

/// Local/global with Anderson acceleration (AndersonAcceleration, Peng et al. 2018,
/// Algorithm 2) and the driver's energy safeguard: g of the accepted iterates never increases,
/// and the returned iterate is never worse than the plain iterate it came from. Solves contact
/// forces like local_global.
class AndersonSolver final : public LocalGlobalSolver {
 public:
  AndersonSolver() : LocalGlobalSolver(&anderson_) {}
  const char* name() const override { return "anderson"; }
  /// Iterates rejected by the safeguard since construction (diagnostics, tests).
  int rejections() const { return anderson_.restarts(); }

 private:
  AndersonAcceleration anderson_;
};

}  // namespace cloth_sim
