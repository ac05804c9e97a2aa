/// @file implicit_euler_problem.h
/// One implicit step (implicit Euler or BDF2) posed as a minimisation (docs/method.md; Liu et
/// al. 2013, eq. 4).
#pragma once

#include "cloth_sim/core/model/model.h"
#include "cloth_sim/core/model/pins.h"
#include "cloth_sim/core/linalg/types.h"
#include "cloth_sim/core/solvers/solver.h"

namespace cloth_sim {

/// Factor exp(-gamma h) applied to the velocity before a step of @p h s: the exact decay of the
/// linear drag dv/dt = -gamma v over one step (Model::damping). Shared by every solver, so all
/// of them integrate the same damped system.
double velocityDecay(const Model& model, double h);

/// The implicit Euler step from state x_n, v_n with step h:
///
///   x_{n+1} = argmin_x g(x),  g(x) = 1/2 (x - y)^T M (x - y) + h^2 E(x),
///   y = x_n + h exp(-gamma h) v_n,
///   E(x) = sum_springs 1/2 k (|x_i - x_j| - r)^2 + sum_soft_pins 1/2 k |x_v - t|^2 - sum_i m_i g.x_i.
///
/// The BDF2 step (Integrator::kBdf2, docs/method.md "BDF2") has the same form with h^2 scaled
/// by 4/9, i.e. with the implicit step h_i = 2h/3 in place of h, and an inertial prediction from
/// the two last states, q = exp(-gamma h):
///
///   y = (4 x_n - x_{n-1}) / 3 + (2h/9) (4 q v_n - q^2 v_{n-1}),
///   v_{n+1} = (3 x_{n+1} - 4 x_n + x_{n-1}) / (2h).
///
/// Without a valid previous state (State::has_previous) it is an implicit Euler step.
///
/// The implicit midpoint step (Integrator::kImplicitMidpoint, docs/method.md "Implicit
/// midpoint") is an implicit Euler step of h_i = h/2 to the midpoint, then the explicit half:
///
///   x_half = argmin 1/2 |x - y|_M^2 + (h/2)^2 E(x),  y = x_n + (h/2) q v_n,
///   x_{n+1} = 2 x_half - x_n,  v_{n+1} = 4 (x_half - x_n) / h - q v_n,
///
/// which is x_{n+1} - x_n = h (v_n + v_{n+1}) / 2 and M (v_{n+1} - v_n) = h f((x_n + x_{n+1}) / 2)
/// (q v_n for v_n: a free damped particle's velocity is then exactly q^n v_0). Hard-pinned
/// particles sit on their targets at the midpoint and end the step there, with the mean
/// velocity (t - x_n) / h (a moving pin is thus half a step early at the midpoint).
///
/// Hard-pinned particles are not unknowns: they sit on their targets in @c inertial and in every
/// iterate. g is in kg m^2 (energy times h_i^2).
struct ImplicitStepProblem {
  const Model* model = nullptr;
  const PinSet* pins = nullptr;
  double h = 0.0;    ///< s, the time step
  /// s, h_i: the step of the h_i^2 E(x) term and of the global matrix M + h_i^2 L; h for
  /// implicit Euler, 2h/3 for BDF2, h/2 for implicit midpoint.
  double implicit_h = 0.0;
  bool bdf2 = false;         ///< a BDF2 step
  bool midpoint = false;     ///< an implicit midpoint step (neither: implicit Euler)
  Points start;              ///< x_n, m
  Points start_velocities;   ///< v_n, m/s (kept as the next step's history)
  Points previous;           ///< x_{n-1}, m (BDF2 only)
  Points inertial;           ///< y, m; hard-pinned particles at their targets

  /// Builds the step of @p h s (SolverInput::h) from @p state (positions x_n, velocities v_n,
  /// and for BDF2 its previous state) and the current pin targets. kBdf2 without
  /// State::has_previous builds implicit Euler.
  static ImplicitStepProblem build(const Model& model, const PinSet& pins, const State& state,
                                   double h, Integrator integrator = Integrator::kImplicitEuler);

  /// g(x), kg m^2. @p x must hold hard-pinned particles at their targets.
  double objective(const Points& x) const;
  /// g(x) when the spring energy at @p x (J) is already known (local/global computes it).
  double objective(const Points& x, double spring_energy) const;
  /// dg/dx (kg m), zero on hard-pinned particles.
  void gradient(const Points& x, Points& grad) const;
  /// The end-of-step state for the minimiser @p x: v_{n+1} = (x - x_n) / h (BDF2:
  /// (3 x - 4 x_n + x_{n-1}) / (2h); implicit midpoint: @p x is x_half and the state is
  /// x_{n+1} = 2 x - x_n, v_{n+1} = 4 (x - x_n) / h - q v_n), time advanced by h, x_n and v_n
  /// kept as its history.
  State finish(const Points& x, double start_time) const;
};

/// All forces on the particles at positions @p x (N): springs, gravity m g, soft pins.
void totalForces(const Model& model, const PinSet& pins, const Points& x, Points& forces);

/// Potential energy of the external and pin forces: soft pins 1/2 k |x - t|^2 minus sum m g.x (J).
double externalPotential(const Model& model, const PinSet& pins, const Points& x);

/// Kinetic energy 1/2 v^T M v of @p state (J).
double kineticEnergy(const Model& model, const State& state);

}  // namespace cloth_sim
