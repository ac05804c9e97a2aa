#include "cloth_sim/core/solvers/baselines/explicit_solvers.h"

#include "cloth_sim/core/solvers/implicit_euler_problem.h"

namespace cloth_sim {
namespace {

/// Hard pins are data: the particle lands on its target, with the velocity that got it there.
void applyHardPins(const PinSet& pins, const Points& start, double h, State& state) {
  for (const Pin& pin : pins.pins()) {
    if (!pin.isHard()) continue;
    state.positions.col(pin.vertex) = pin.target;
    state.velocities.col(pin.vertex) = (pin.target - start.col(pin.vertex)) / h;
  }
}

}  // namespace

SolveResult ExplicitEulerSolver::step(const SolverInput& in, const SolverSettings& settings,
                                      State& state) {
  requireIntegrator(*this, settings.integrator);
  state.has_previous = false;  // no implicit step's history
  const double h = in.h;
  const Points start = state.positions;
  Points forces;
  totalForces(in.model, in.pins, state.positions, forces);
  state.velocities = velocityDecay(in.model, h) * state.velocities +
                     h * forces * in.model.mass.cwiseInverse().asDiagonal();
  state.positions += h * state.velocities;
  applyHardPins(in.pins, start, h, state);
  state.time += h;
  return SolveResult{1, 0.0, false};
}

SolveResult VerletSolver::step(const SolverInput& in, const SolverSettings& settings,
                               State& state) {
  requireIntegrator(*this, settings.integrator);
  state.has_previous = false;  // no implicit step's history
  const double h = in.h;
  const auto inverse_mass = in.model.mass.cwiseInverse().asDiagonal();
  const Points start = state.positions;
  Points forces;
  totalForces(in.model, in.pins, state.positions, forces);
  const Points accel_start = forces * inverse_mass;
  const Points damped_velocity = velocityDecay(in.model, h) * state.velocities;
  state.positions += h * damped_velocity + (0.5 * h * h) * accel_start;
  for (const Pin& pin : in.pins.pins()) {
    if (pin.isHard()) state.positions.col(pin.vertex) = pin.target;
  }
  totalForces(in.model, in.pins, state.positions, forces);
  state.velocities = damped_velocity + (0.5 * h) * (accel_start + forces * inverse_mass);
  applyHardPins(in.pins, start, h, state);
  state.time += h;
  return SolveResult{1, 0.0, false};
}

}  // namespace cloth_sim
