/// @file local_global_driver.h
/// The one iteration loop of local_global, chebyshev and anderson: local/global iterations, an
/// optional acceleration, the energy safeguard, the observer and the stop test.
#pragma once

#include "cloth_sim/core/solvers/local_global/iteration_hooks.h"
#include "cloth_sim/core/solvers/local_global/local_global_problem.h"
#include "cloth_sim/core/solvers/solver.h"

namespace cloth_sim {

/// How the driver turns the plain local/global iterate into the next iterate.
class Acceleration {
 public:
  virtual ~Acceleration() = default;
  /// Prepares a step (settings, revision-dependent constants); forgets the last step's history.
  virtual void begin(const SolverInput& input, const SolverSettings& settings) = 0;
  /// The safeguard rejected the last extrapolated iterate: start again from the plain one.
  virtual void restart() = 0;
  /// Given the previous iterate @p x_prev, the current one @p x and the plain local/global
  /// iterate @p x_hat = G(x), writes the next iterate into @p x_next and returns true, or
  /// returns false to take @p x_hat itself (no extrapolation, @p x_next untouched).
  virtual bool extrapolate(const NodeBuffer& x_prev, const NodeBuffer& x, const NodeBuffer& x_hat,
                           NodeBuffer& x_next) = 0;
};

/// The driver's iterates, kept by the solver from step to step so that a substep allocates
/// only its initial guess (at 128 x 128, allocating and first touching all five each substep
/// was about 2.5 % of a run).
struct LocalGlobalIterates {
  NodeBuffer start, x, x_prev, x_hat, x_hat_prev, x_next;
};

/// Runs one step of @p problem (begin() done) with @p acceleration (nullptr: plain local/global)
/// and ends it (finishStep), in @p iterates (any contents). Every local/global solve counts as
/// an iteration.
///
/// Safeguard: the local step of the next iteration gives g of an extrapolated iterate; when it
/// is above g of the iterate it came from, it is replaced by the plain iterate from there (which
/// never raises g), the acceleration restarts, and that costs one more solve. At the end (and
/// for the observer) an extrapolated iterate worse than the plain iterate it was built from is
/// replaced by that one (two spring passes, no solve). So g of the accepted iterates never
/// increases, and the result is never worse than the plain local/global iterate.
SolveResult runLocalGlobal(LocalGlobalProblem& problem, Acceleration* acceleration,
                           IterationHooks& hooks, const SolverSettings& settings, State& state,
                           LocalGlobalIterates& iterates);

}  // namespace cloth_sim
