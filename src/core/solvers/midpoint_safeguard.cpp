#include "cloth_sim/core/solvers/midpoint_safeguard.h"

#include <stdexcept>
#include <utility>

#include "cloth_sim/core/model/spring_kernels.h"
#include "cloth_sim/core/solvers/implicit_euler_problem.h"

namespace cloth_sim {

StepEnergy stepEnergy(const Model& model, const PinSet& pins, const State& state) {
  double kinetic = kineticEnergy(model, state);
  for (const Pin& pin : pins.pins()) {
    if (pin.isHard())
      kinetic -= 0.5 * model.mass[pin.vertex] * state.velocities.col(pin.vertex).squaredNorm();
  }
  const double mechanical = kinetic + springEnergy(model.springs, state.positions);
  return {mechanical, mechanical + externalPotential(model, pins, state.positions)};
}

MidpointSafeguard::MidpointSafeguard(std::unique_ptr<Solver> inner) : inner_(std::move(inner)) {
  if (!inner_) throw std::invalid_argument("MidpointSafeguard: no solver to wrap");
}

SolveResult MidpointSafeguard::step(const SolverInput& input, const SolverSettings& settings,
                                    State& state) {
  if (settings.integrator != Integrator::kImplicitMidpoint) {
    return inner_->step(input, settings, state);
  }
  const State before = state;
  const StepEnergy energy_before = stepEnergy(input.model, input.pins, state);
  SolveResult solved = inner_->step(input, settings, state);
  const double allowed = kGain * energy_before.mechanical +
                         kGainFloor * input.model.mass.sum() * input.model.gravity.norm();
  if (stepEnergy(input.model, input.pins, state).total - energy_before.total > allowed) {
    state = before;
    SolverSettings euler = settings;
    euler.integrator = Integrator::kImplicitEuler;
    SolverInput half{input.model, input.pins, 0.5 * input.h, input.revision, nullptr};
    half.iteration_tolerance = 0.5 * input.iteration_tolerance;  // two steps share it
    half.deadline = input.deadline;
    half.min_iterations_at_deadline = input.min_iterations_at_deadline;
    inner_->step(half, euler, state);
    solved = inner_->step(half, euler, state);
    state.time = before.time + input.h;
    solved.midpoint_fallback = true;
  }
  return solved;
}

}  // namespace cloth_sim
