/// @file midpoint_safeguard.h
/// The implicit midpoint energy safeguard, as a wrapper around any solver (docs/method.md,
/// "Implicit midpoint").
#pragma once

#include <memory>

#include "cloth_sim/core/model/model.h"
#include "cloth_sim/core/model/pins.h"
#include "cloth_sim/core/solvers/solver.h"

namespace cloth_sim {

/// Energies of a state as the safeguard weighs them (J).
struct StepEnergy {
  double mechanical;  ///< kinetic + springs
  double total;       ///< mechanical + gravity and soft pins
};

/// The energy of @p state as Simulation::totalEnergy, but without the hard-pinned particles'
/// kinetic energy: their velocity is prescribed (a pin teleported by 1 m in one step moves at
/// 1 m / h), not energy the cloth can use.
StepEnergy stepEnergy(const Model& model, const PinSet& pins, const State& state);

/// A Solver around another one. Under Integrator::kImplicitMidpoint a step that gains more
/// energy than a tolerance is redone, from its start, as two implicit Euler steps of h/2 by the
/// inner solver (SolverInput::h halved; SolveResult::midpoint_fallback says so); under any other
/// integrator it is the inner solver, call for call.
///
/// Why: without moving pins the energy of a step cannot grow (the damping only removes it); a
/// converged midpoint step keeps it to O(h^2) and an under-iterated one loses some. Plain
/// midpoint on stiff cloth at large steps gains energy step after step until it explodes
/// (docs/benchmark.md, "Stability"). The two half steps have the midpoint's matrix,
/// M + (h/2)^2 L (same revision and implicit step h_i, so no refactorization), and implicit
/// Euler is L-stable. Contacts are left to the projection after the step, as under midpoint.
/// A growth slower than the tolerance per step is not caught (kept as measured: a running
/// budget caught it, but also fired on the peers' cloth and cost it most of its energy).
class MidpointSafeguard : public Solver {
 public:
  /// A step may gain this fraction of the kinetic plus spring energy at its start (J / J) ...
  static constexpr double kGain = 1e-2;
  /// ... plus this times m |g| (J / N, i.e. m), so that a cloth released at rest is not held to
  /// its exact energy.
  static constexpr double kGainFloor = 1e-4;

  /// Wraps @p inner (not null).
  explicit MidpointSafeguard(std::unique_ptr<Solver> inner);

  /// The inner solver's name: the wrapper is not a solver of its own.
  const char* name() const override { return inner_->name(); }
  /// The inner solver's step of input.h; under kImplicitMidpoint checked and, if it gained
  /// energy, redone as two inner implicit Euler steps of input.h / 2 (state.time still advances
  /// by input.h). Returns the last inner step's result, midpoint_fallback set if redone.
  SolveResult step(const SolverInput& input, const SolverSettings& settings, State& state) override;
  void requireSettings(const SolverSettings& settings) const override {
    inner_->requireSettings(settings);
  }
  /// The inner solver's factorizations.
  int factorizationCount() const override { return inner_->factorizationCount(); }
  /// The inner solver's warm start.
  SolverCarry carriedOver() const override { return inner_->carriedOver(); }
  void carryOver(const SolverCarry& carry) override { inner_->carryOver(carry); }

  Solver& inner() { return *inner_; }
  const Solver& inner() const { return *inner_; }

 private:
  std::unique_ptr<Solver> inner_;
};

}  // namespace cloth_sim
