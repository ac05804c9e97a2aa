#include "cloth_sim/core/solvers/local_global/local_global_driver.h"

#include <limits>

namespace cloth_sim {

SolveResult runLocalGlobal(LocalGlobalProblem& problem, Acceleration* acceleration,
                           IterationHooks& hooks, const SolverSettings& settings, State& state,
                           LocalGlobalIterates& iterates) {
  hooks.clearTrace();
  iterates.start = problem.initialGuess(settings);
  const NodeBuffer& start = iterates.start;
  // x_hat = G(x) (the plain iterate), x_hat_prev = G(x_prev): the fallbacks of the safeguard.
  NodeBuffer &x = iterates.x, &x_prev = iterates.x_prev, &x_hat = iterates.x_hat,
             &x_hat_prev = iterates.x_hat_prev, &x_next = iterates.x_next;
  x = start;
  x_prev = start;
  x_hat.assign(start.size(), 0.0);
  x_hat_prev.assign(start.size(), 0.0);
  x_next.assign(start.size(), 0.0);
  double g_prev = std::numeric_limits<double>::infinity();
  bool accelerated = false;  // whether x came from an extrapolation
  int solves = 0;
  const int max_solves = settings.max_iterations;
  const double tolerance = problem.iterationTolerance();
  IterationError error;
  SolveResult result;
  while (solves < max_solves) {
    double g = problem.iterate(x, x_hat);
    ++solves;
    // Error control: the plain iterate's change estimates the distance left to the solution.
    if (tolerance > 0.0 && error.add(problem.rmsDistance(x_hat, x)) <= tolerance) {
      x = x_hat;  // the plain iterate, which never raises g
      accelerated = false;
      result.converged = true;
      hooks.observe(solves, x, problem);
      break;
    }
    if (accelerated && g > g_prev) {
      x = x_hat_prev;  // g(G(x_prev)) <= g_prev
      accelerated = false;
      acceleration->restart();
      if (solves >= max_solves) {
        hooks.observe(solves, x, problem);  // the step ends on this plain iterate
        break;
      }
      g = problem.iterate(x, x_hat);
      ++solves;
    }
    hooks.record(g);
    accelerated = acceleration != nullptr && acceleration->extrapolate(x_prev, x, x_hat, x_next);
    // Without extrapolation x_hat_prev is never read: the plain iterate moves, not copied.
    if (!accelerated) x_next.swap(x_hat);
    result.iterations = solves;
    // Two norm passes: only when they can be read (the stop test, an observer that may stop
    // here, or the last iterations).
    if (settings.tolerance > 0.0 || hooks.observing() || solves + 1 >= max_solves)
      result.convergence = relativeChange(x_next, x, start);
    x_prev.swap(x);
    x_hat_prev.swap(x_hat);
    g_prev = g;
    x.swap(x_next);
    if (hooks.observing()) {  // what the step would return if it stopped here (see the end)
      const bool plain_better =
          accelerated && problem.objectiveAt(x) > problem.objectiveAt(x_hat_prev);
      if (!hooks.observe(solves, plain_better ? x_hat_prev : x, problem)) {
        if (plain_better) x = x_hat_prev;
        accelerated = false;
        break;
      }
    }
    if (settings.tolerance > 0.0 && result.convergence < settings.tolerance) {
      result.converged = true;
      break;
    }
    if (solves < max_solves && problem.pastDeadline(solves)) {
      result.cut = true;
      break;
    }
  }
  result.iterations = solves;
  result.iteration_error = tolerance > 0.0 ? error.estimate() : 0.0;
  if (accelerated && problem.objectiveAt(x) > problem.objectiveAt(x_hat_prev)) x = x_hat_prev;
  if (hooks.tracing()) hooks.record(problem.objectiveAt(x));
  problem.finishStep(x, state);
  result.used_contacts = problem.solvesContacts();
  return result;
}

}  // namespace cloth_sim
