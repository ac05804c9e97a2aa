#include "cloth_sim/core/solvers/implicit_euler_problem.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "cloth_sim/core/model/spring_kernels.h"

namespace cloth_sim {

double velocityDecay(const Model& model, double h) { return std::exp(-model.damping * h); }

StepRecurrence StepRecurrence::of(const State& state, double h, Integrator integrator,
                                  double damping) {
  StepRecurrence r;
  r.h = h;
  const double q = std::exp(-damping * h);
  r.bdf2 = integrator == Integrator::kBdf2 && state.has_previous && state.previous_step > 0.0 &&
           state.previous_positions.cols() == state.positions.cols() &&
           state.previous_velocities.cols() == state.positions.cols();
  if (r.bdf2) {
    const double omega = h / state.previous_step;
    r.constant = omega == 1.0;
    const double a1 = (1.0 + omega) * (1.0 + omega) / (1.0 + 2.0 * omega);
    const double a0 = omega * omega / (1.0 + 2.0 * omega);
    r.implicit_h = h * (1.0 + omega) / (1.0 + 2.0 * omega);
    // Each past velocity decays by its age (q, q q_p): exact for a free damped particle.
    const double q_previous = q * std::exp(-damping * state.previous_step);
    r.decay = q;
    r.cx = a1;
    r.cxp = -a0;
    r.cv = r.implicit_h * a1 * q;
    r.cvp = -r.implicit_h * a0 * q_previous;
    r.dx = a1;
    r.dxp = -a0;
  } else if (integrator == Integrator::kImplicitMidpoint) {
    r.midpoint = true;
    r.implicit_h = 0.5 * h;
    r.cv = r.implicit_h * q;
  } else {
    r.implicit_h = h;
    r.cv = h * q;
  }
  return r;
}

Vec3 StepRecurrence::inertial(const State& state, Eigen::Index i) const {
  if (constant) {
    return (4.0 * state.positions.col(i) - state.previous_positions.col(i)) / 3.0 +
           (2.0 * h / 9.0) * (4.0 * decay * state.velocities.col(i) -
                              decay * decay * state.previous_velocities.col(i));
  }
  Vec3 y = cx * state.positions.col(i) + cv * state.velocities.col(i);
  if (bdf2) y += cxp * state.previous_positions.col(i) + cvp * state.previous_velocities.col(i);
  return y;
}

ImplicitStepProblem ImplicitStepProblem::build(const Model& model, const PinSet& pins,
                                               const State& state, double h,
                                               Integrator integrator) {
  ImplicitStepProblem p;
  p.model = &model;
  p.pins = &pins;
  p.h = h;
  p.start = state.positions;
  p.start_velocities = state.velocities;
  p.recurrence = StepRecurrence::of(state, h, integrator, model.damping);
  const StepRecurrence& r = p.recurrence;
  p.bdf2 = r.bdf2;
  p.midpoint = r.midpoint;
  p.implicit_h = r.implicit_h;
  if (r.constant) {
    const double q = r.decay;
    p.inertial = (4.0 * state.positions - state.previous_positions) / 3.0 +
                 (2.0 * h / 9.0) * (4.0 * q * state.velocities - q * q * state.previous_velocities);
  } else {
    p.inertial = r.cx * state.positions + r.cv * state.velocities;
    if (p.bdf2) p.inertial += r.cxp * state.previous_positions + r.cvp * state.previous_velocities;
  }
  if (p.bdf2) p.previous = state.previous_positions;
  for (const Pin& pin : pins.pins()) {
    if (pin.isHard()) p.inertial.col(pin.vertex) = pin.target;
  }
  return p;
}

bool localErrors(const Model& model, const PinSet& pins, const State& after,
                 const Points& older_velocities, double older_step, Integrator integrator,
                 const std::vector<char>& skip, Points& errors, std::vector<char>& estimated) {
  const Eigen::Index n = after.positions.cols();
  errors.setZero(3, n);
  estimated.assign(static_cast<std::size_t>(n), 0);
  if (!after.has_previous || after.previous_step <= 0.0) return false;
  std::fill(estimated.begin(), estimated.end(), 1);
  for (const Pin& pin : pins.pins()) {
    if (pin.isHard()) estimated[pin.vertex] = 0;
  }
  for (std::size_t i = 0; i < skip.size() && i < estimated.size(); ++i) {
    if (skip[i]) estimated[i] = 0;
  }
  const double h = after.previous_step;
  const Points& x_n = after.previous_positions;
  const Points& v_n = after.previous_velocities;
  const bool third_order = integrator != Integrator::kImplicitEuler && older_step > 0.0 &&
                           older_velocities.cols() == n;
  double weight = 0.0;
  if (third_order) {
    // x''' from the velocities' second divided difference:
    // x''' ~ 2 ((v_{n+1} - v_n) / h - (v_n - v_{n-1}) / h_p) / (h + h_p); error C h^3 x'''.
    const double omega = h / older_step;
    const double c = integrator == Integrator::kBdf2
                         ? (1.0 + omega) * (1.0 + omega) / (6.0 * omega * (1.0 + 2.0 * omega))
                         : 1.0 / 12.0;
    weight = c * h * h * h * 2.0 / (h + older_step);
  }
  const double hq = h * std::exp(-model.damping * h);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!estimated[i]) continue;
    if (third_order) {
      const Vec3 slope_new = (after.velocities.col(i) - v_n.col(i)) / h;
      const Vec3 slope_old = (v_n.col(i) - older_velocities.col(i)) / older_step;
      errors.col(i) = weight * (slope_new - slope_old);
    } else {
      errors.col(i) = 0.5 * (after.positions.col(i) - x_n.col(i) - hq * v_n.col(i));
    }
  }
  return true;
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
    const StepRecurrence& r = recurrence;
    next.positions = x;
    if (r.constant) next.velocities = (3.0 * x - 4.0 * start + previous) / (2.0 * h);
    else if (bdf2) next.velocities = (x - r.dx * start - r.dxp * previous) / r.implicit_h;
    else next.velocities = (x - start) / h;
  }
  next.time = start_time + h;
  next.previous_positions = start;
  next.previous_velocities = start_velocities;
  next.previous_step = h;
  next.has_previous = true;
  return next;
}

}  // namespace cloth_sim
