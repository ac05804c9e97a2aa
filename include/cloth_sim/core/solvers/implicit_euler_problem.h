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
/// The BDF2 step (Integrator::kBdf2, docs/method.md "BDF2") has the same form with the
/// implicit step h_i = beta in place of h and an inertial prediction from the two last states
/// (StepRecurrence). For a step h after a step h_p (omega = h / h_p; variable-step BDF2):
///
///   a1 = (1 + omega)^2 / (1 + 2 omega),  a0 = omega^2 / (1 + 2 omega),
///   beta = h (1 + omega) / (1 + 2 omega),
///   y = a1 x_n - a0 x_{n-1} + beta (a1 q v_n - a0 q q_p v_{n-1}),
///   v_{n+1} = (x_{n+1} - a1 x_n + a0 x_{n-1}) / beta,
///
/// q = exp(-gamma h), q_p = exp(-gamma h_p) (each past velocity decays by its age). At a
/// constant step (omega = 1): y = (4 x_n - x_{n-1}) / 3 + (2h/9) (4 q v_n - q^2 v_{n-1}),
/// v_{n+1} = (3 x_{n+1} - 4 x_n + x_{n-1}) / (2h), h_i = 2h/3.
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
/// The linear recurrence of one implicit step of @p h s from a state (docs/method.md, "BDF2"):
/// the inertial prediction y = cx x_n + cxp x_{n-1} + cv v_n + cvp v_{n-1}, the implicit step h_i
/// of g's h_i^2 E(x) term and of the matrix M + h_i^2 L, and (implicit Euler, BDF2) the end
/// velocity v_{n+1} = (x_{n+1} - dx x_n - dxp x_{n-1}) / h_i. Implicit midpoint: y and h_i of its
/// half step (ImplicitStepProblem::finish extrapolates). One place for the coefficients, shared
/// by every implicit solver, the pin loads and the contacts.
struct StepRecurrence {
  bool bdf2 = false;      ///< a BDF2 step (needs State::has_previous)
  bool midpoint = false;  ///< an implicit midpoint step (neither: implicit Euler)
  /// A BDF2 step of the same size as the one before (omega = 1): computed as the constant-step
  /// formulas are written above, so that a run at fixed substeps is the same to the bit.
  bool constant = false;
  double h = 0.0;         ///< s, the step
  double implicit_h = 0.0;  ///< s, h_i
  double cx = 1.0, cxp = 0.0, cv = 0.0, cvp = 0.0;  ///< weights of y (1, 1, s, s)
  double dx = 1.0, dxp = 0.0;                       ///< weights of v_{n+1} (1, 1)
  double decay = 1.0;  ///< exp(-gamma h) of a BDF2 step (Model::damping)

  /// The recurrence of a step of @p h s with @p integrator from @p state, for a model damped
  /// at @p damping 1/s (Model::damping). kBdf2 without a usable history is implicit Euler.
  static StepRecurrence of(const State& state, double h, Integrator integrator, double damping);
  /// y for particle column @p i of @p state.
  Vec3 inertial(const State& state, Eigen::Index i) const;
};

/// The local truncation error of the implicit step that ended at @p after, estimated from the
/// step itself and its history, per particle as a vector (m). docs/method.md, "Error control".
/// The step's start is after's history (previous_positions x_n, previous_velocities v_n,
/// previous_step h); @p older_velocities is v_{n-1} and @p older_step its step h_p (0: no
/// history).
///  - implicit Euler: (x_{n+1} - x_n - h q v_n) / 2 (= h^2 a / 2, the distance the step's
///    constant acceleration puts a particle beyond the exact quadratic);
///  - BDF2 (variable step, omega = h / h_p): C(omega) h^3 x''', C = (1 + omega)^2 /
///    (6 omega (1 + 2 omega)) (2/9 at omega = 1), x''' from the second divided difference of
///    v_{n-1}, v_n, v_{n+1};
///  - implicit midpoint: h^3 x''' / 12, x''' as for BDF2;
///  - without history (BDF2's first step is implicit Euler): implicit Euler's.
/// @p errors (3 x N) gets each estimated particle's error and zero elsewhere; @p estimated (N)
/// is 1 where a particle is estimated, 0 where it is hard pinned (its motion is prescribed) or
/// in @p skip (empty, or one per particle): Simulation skips those a contact touched in this
/// step or the one before, whose velocity jumps there (an impact, a stop) and has no
/// derivative to estimate: the error of contact is the contact model's, not the step size's.
/// @p integrator as configured; @p pins: the pins of the step. Returns false, with nothing
/// estimated, when @p after has no history (an explicit solver).
bool localErrors(const Model& model, const PinSet& pins, const State& after,
                 const Points& older_velocities, double older_step, Integrator integrator,
                 const std::vector<char>& skip, Points& errors, std::vector<char>& estimated);

struct ImplicitStepProblem {
  const Model* model = nullptr;
  const PinSet* pins = nullptr;
  double h = 0.0;    ///< s, the time step
  /// s, h_i: the step of the h_i^2 E(x) term and of the global matrix M + h_i^2 L; h for
  /// implicit Euler, 2h/3 for BDF2, h/2 for implicit midpoint.
  double implicit_h = 0.0;
  bool bdf2 = false;         ///< a BDF2 step
  bool midpoint = false;     ///< an implicit midpoint step (neither: implicit Euler)
  StepRecurrence recurrence; ///< y's and v_{n+1}'s weights
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
