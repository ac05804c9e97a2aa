/// @file implicit_euler_problem.h
/// One implicit Euler step posed as a minimisation (docs/method.md; Liu et al. 2013, eq. 4).
#pragma once

#include "cloth_sim/core/model/model.h"
#include "cloth_sim/core/model/pins.h"
#include "cloth_sim/core/linalg/types.h"

namespace cloth_sim {

/// Factor exp(-gamma h) applied to the velocity before a step: the exact decay of the linear
/// drag dv/dt = -gamma v over one step (Model::damping). Shared by every solver, so all of them
/// integrate the same damped system.
double velocityDecay(const Model& model);

/// The implicit Euler step from state x_n, v_n with step h:
///
///   x_{n+1} = argmin_x g(x),  g(x) = 1/2 (x - y)^T M (x - y) + h^2 E(x),
///   y = x_n + h exp(-gamma h) v_n,
///   E(x) = sum_springs 1/2 k (|x_i - x_j| - r)^2 + sum_soft_pins 1/2 k |x_v - t|^2 - sum_i m_i g.x_i.
///
/// Hard-pinned particles are not unknowns: they sit on their targets in @c inertial and in every
/// iterate. g is in kg m^2 (energy times h^2).
struct ImplicitStepProblem {
  const Model* model = nullptr;
  const PinSet* pins = nullptr;
  double h = 0.0;    ///< s
  Points start;      ///< x_n, m
  Points inertial;   ///< y, m; hard-pinned particles at their targets

  /// Builds y from @p state (positions x_n, velocities v_n) and the current pin targets.
  static ImplicitStepProblem build(const Model& model, const PinSet& pins, const State& state);

  /// g(x), kg m^2. @p x must hold hard-pinned particles at their targets.
  double objective(const Points& x) const;
  /// g(x) when the spring energy at @p x (J) is already known (local/global computes it).
  double objective(const Points& x, double spring_energy) const;
  /// dg/dx (kg m), zero on hard-pinned particles.
  void gradient(const Points& x, Points& grad) const;
  /// The end-of-step state for positions @p x: v_{n+1} = (x - x_n) / h, time advanced by h.
  State finish(const Points& x, double start_time) const;
};

/// All forces on the particles at positions @p x (N): springs, gravity m g, soft pins.
void totalForces(const Model& model, const PinSet& pins, const Points& x, Points& forces);

/// Potential energy of the external and pin forces: soft pins 1/2 k |x - t|^2 minus sum m g.x (J).
double externalPotential(const Model& model, const PinSet& pins, const Points& x);

}  // namespace cloth_sim
