#include "cloth_sim/core/solvers/implicit_euler_problem.h"

#include <cmath>

#include "cloth_sim/core/model/spring_kernels.h"

namespace cloth_sim {

double velocityDecay(const Model& model) { return std::exp(-model.damping * model.time_step); }

ImplicitStepProblem ImplicitStepProblem::build(const Model& model, const PinSet& pins,
                                               const State& state) {
  ImplicitStepProblem p;
  p.model = &model;
  p.pins = &pins;
  p.h = model.time_step;
  p.start = state.positions;
  p.inertial = state.positions + (p.h * velocityDecay(model)) * state.velocities;
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

double ImplicitStepProblem::objective(const Points& x) const {
  return objective(x, springEnergy(model->springs, x));
}

double ImplicitStepProblem::objective(const Points& x, double spring_energy) const {
  const double inertia = 0.5 * ((x - inertial).colwise().squaredNorm() * model->mass)(0);
  return inertia + h * h * (spring_energy + externalPotential(*model, *pins, x));
}

void totalForces(const Model& model, const PinSet& pins, const Points& x, Points& forces) {
  forces = model.gravity * model.mass.transpose();
  addSpringForces(model.springs, x, forces);
  for (const Pin& pin : pins.pins()) {
    if (!pin.isHard()) forces.col(pin.vertex) -= pin.stiffness * (x.col(pin.vertex) - pin.target);
  }
}

void ImplicitStepProblem::gradient(const Points& x, Points& grad) const {
  // M (x - y) - h^2 f, f the spring, gravity and soft-pin forces.
  Points forces;
  totalForces(*model, *pins, x, forces);
  grad = (x - inertial) * model->mass.asDiagonal() - h * h * forces;
  for (const Pin& pin : pins->pins()) {
    if (pin.isHard()) grad.col(pin.vertex).setZero();
  }
}

State ImplicitStepProblem::finish(const Points& x, double start_time) const {
  State next;
  next.positions = x;
  next.velocities = (x - start) / h;
  next.time = start_time + h;
  return next;
}

}  // namespace cloth_sim
