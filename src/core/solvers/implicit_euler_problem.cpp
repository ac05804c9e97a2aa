#include "cloth_sim/core/solvers/implicit_euler_problem.h"

#include <cmath>

#include "cloth_sim/core/model/spring_kernels.h"

namespace cloth_sim {

double velocityDecay(const Model& model, double h) { return std::exp(-model.damping * h); }

ImplicitStepProblem ImplicitStepProblem::build(const Model& model, const PinSet& pins,
                                               const State& state, double h,
                                               Integrator integrator) {
  ImplicitStepProblem p;
  p.model = &model;
  p.pins = &pins;
  p.h = h;
  p.start = state.positions;
  p.start_velocities = state.velocities;
  p.bdf2 = integrator == Integrator::kBdf2 && state.has_previous &&
           state.previous_positions.cols() == state.positions.cols() &&
           state.previous_velocities.cols() == state.positions.cols();
  if (p.bdf2) {
    // Each past velocity decays by its age (q, q^2): exact for a free damped particle, whose
    // velocities then stay q^n v_0, as implicit Euler's q v_n is.
    const double q = velocityDecay(model, p.h);
    p.implicit_h = 2.0 * p.h / 3.0;
    p.previous = state.previous_positions;
    p.inertial = (4.0 * state.positions - state.previous_positions) / 3.0 +
                 (2.0 * p.h / 9.0) * (4.0 * q * state.velocities - q * q * state.previous_velocities);
  } else if (integrator == Integrator::kImplicitMidpoint) {
    p.midpoint = true;
    p.implicit_h = 0.5 * p.h;
    p.inertial = state.positions + (0.5 * p.h * velocityDecay(model, p.h)) * state.velocities;
  } else {
    p.implicit_h = p.h;
    p.inertial = state.positions + (p.h * velocityDecay(model, p.h)) * state.velocities;
  }
  for (const Pin& pin : pins.pins()) {
    if (pin.isHard()) p.inertial.col(pin.vertex) = pin.target;
  }
  return p;
}

double externalPotential(const Model& model, const PinSet& pins, const Points& x) {
  double potential = -(x * model.mass).dot(model.gravity);
  for (const Pin& pin : pins.pins()) {
    if (!pin.isHard()) potential += 0.5 * pin.stiffness * (x.col(pin.vertex) - pin.target).squaredNorm();
  }
  return potential;
}

double kineticEnergy(const Model& model, const State& state) {
  return 0.5 * (state.velocities.colwise().squaredNorm() * model.mass)(0);
}

double ImplicitStepProblem::objective(const Points& x) const {
  return objective(x, springEnergy(model->springs, x));
}

double ImplicitStepProblem::objective(const Points& x, double spring_energy) const {
  const double inertia = 0.5 * ((x - inertial).colwise().squaredNorm() * model->mass)(0);
  return inertia + implicit_h * implicit_h * (spring_energy + externalPotential(*model, *pins, x));
}

void totalForces(const Model& model, const PinSet& pins, const Points& x, Points& forces) {
  forces = model.gravity * model.mass.transpose();
  addSpringForces(model.springs, x, forces);
  for (const Pin& pin : pins.pins()) {
    if (!pin.isHard()) forces.col(pin.vertex) -= pin.stiffness * (x.col(pin.vertex) - pin.target);
  }
}

void ImplicitStepProblem::gradient(const Points& x, Points& grad) const {
  // M (x - y) - h_i^2 f, f the spring, gravity and soft-pin forces.
  Points forces;
  totalForces(*model, *pins, x, forces);
  grad = (x - inertial) * model->mass.asDiagonal() - implicit_h * implicit_h * forces;
  for (const Pin& pin : pins->pins()) {
    if (pin.isHard()) grad.col(pin.vertex).setZero();
  }
}

State ImplicitStepProblem::finish(const Points& x, double start_time) const {
  State next;
  if (midpoint) {
    next.positions = 2.0 * x - start;
    next.velocities = (4.0 / h) * (x - start) - velocityDecay(*model, h) * start_velocities;
    for (const Pin& pin : pins->pins()) {
      // Extrapolating a pinned particle would put it at 2 t - x_n: it follows its target.
      if (!pin.isHard()) continue;
      next.positions.col(pin.vertex) = pin.target;
      next.velocities.col(pin.vertex) = (pin.target - start.col(pin.vertex)) / h;
    }
  } else {
    next.positions = x;
    if (bdf2) next.velocities = (3.0 * x - 4.0 * start + previous) / (2.0 * h);
    else next.velocities = (x - start) / h;
  }
  next.time = start_time + h;
  next.previous_positions = start;
  next.previous_velocities = start_velocities;
  next.has_previous = true;
  return next;
}

}  // namespace cloth_sim
