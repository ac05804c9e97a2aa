/// @file substep.h
/// One implicit step of a frame with its contacts: the substep pipeline of Simulation::step.
#pragma once

#include <chrono>

#include <cstdint>
#include <vector>

#include "cloth_sim/core/collision/colliders.h"
#include "cloth_sim/core/collision/contact_forces.h"
#include "cloth_sim/core/collision/self_contact.h"
#include "cloth_sim/core/linalg/types.h"
#include "cloth_sim/core/model/model.h"
#include "cloth_sim/core/model/pins.h"
#include "cloth_sim/core/simulation/frame_error.h"
#include "cloth_sim/core/simulation/step_report.h"
#include "cloth_sim/core/solvers/pin_reactions.h"
#include "cloth_sim/core/solvers/solver.h"

namespace cloth_sim {

/// The parts of a simulation a substep reads and writes.
struct SubstepWorld {
  const Model& model;
  const SolverSettings& settings;
  const std::vector<char>& movable;  ///< per particle, false if hard-pinned (collisions skip it)
  Solver& solver;                    ///< the user's solver in its MidpointSafeguard
  SelfContact* self_contact;         ///< null when self-contact is off
  State& state;
  Colliders& colliders;
  std::vector<Vec3>& pin_loads;  ///< N, per pin of the substep (PinReactions)
  /// The frame's deadline (SolverInput::deadline; max(): none).
  std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();
  /// SolverInput::min_iterations_at_deadline.
  int min_iterations_at_deadline = 1;
};

/// One implicit step of h, in this order:
///
/// 1. the spheres advance over h (Colliders::advance: kinematic at their velocity, dynamic
///    balls under gravity and drag);
/// 2. the contacts begin: one CollisionStep {h, mass, movable, start positions} for the
///    substep, ContactForces::beginStep binds the contact forces to the colliders;
/// 3. the solve: the solver on SolverInput{model, pins, h, revision, contacts};
/// 4. the pin reactions: PinReactions (begun before the solve) turns the solve into each pin's
///    load, before any collision response moves a soft-pinned particle;
/// 5. the contacts finish: ContactForces::finish hands the balls' new positions back (only if
///    the solver solved the contacts);
/// 6. the self-contact bound: SelfContact::limitDisplacement bounds each particle's move (before
///    the colliders, so that a collider's own correction is never shortened);
/// 7. the collision projection: resolveCollisions moves the particles out of the colliders;
/// 8. the sphere impacts: resolveSphereImpacts (ball against ball and ground);
/// 9. the self-contact resolve: SelfContact::resolve pushes apart the cloth's particles in
///    contact with each other.
///
/// With nothing to collide with (no collider, self-contact off) only 3 and 4 run. Steps 6 and 9
/// run only with self-contact on. The contact forces' warm start is kept from substep to
/// substep.
class SubstepPipeline {
 public:
  /// Starts a frame: the frame's error estimate (FrameError) and its iteration errors from zero.
  void beginFrame(Eigen::Index particles) {
    frame_error_.begin(particles);
    iteration_errors_ = 0.0;
  }
  /// m: the frame's error estimate from the substeps run since beginFrame (FrameError::rms).
  double frameErrorEstimate() const { return frame_error_.rms(); }
  /// The contact forces of the last substep (ContactForces::addSelfPushes).
  const ContactForces& contactForces() const { return contacts_; }
  /// One substep of @p h s with @p pins at @p revision (SolverInput), its iterations stopped at
  /// an estimated iteration error of @p iteration_tolerance m (0: the settings' count); adds its
  /// substep, iterations, convergence, iteration error, solve time, contacts, self-contacts and
  /// midpoint fallback to @p report, and with @p estimate_error adds its local truncation errors
  /// (localErrors) to the frame's (frameErrorEstimate).
  void run(const SubstepWorld& world, const PinSet& pins, double h, std::uint64_t revision,
           double iteration_tolerance, bool estimate_error, StepReport& report);
  /// Forgets the contact forces' warm start (a rollback or reset: it led there, or is stale).
  void forgetContacts() {
    contacts_ = ContactForces();
    touched_.clear();
    touched_before_.clear();
  }

 private:
  /// The solver's step on @p input, its iterations and time added to @p report.
  SolveResult solve(const SubstepWorld& world, const SolverInput& input, StepReport& report);

  /// The substep itself (run() adds the error estimate around it).
  void collide(const SubstepWorld& world, const PinSet& pins, double h, std::uint64_t revision,
               double iteration_tolerance, StepReport& report);

  ContactForces contacts_;  ///< in-solve contact forces, warm-started across substeps
  PinReactions reactions_;
  Points older_velocities_;  ///< m/s, v_{n-1} of the substep being estimated
  double older_step_ = 0.0;  ///< s, its step (0: no history)
  /// Per particle: a contact touched it in this substep (touched_) or the one before
  /// (touched_before_); both are left out of the error estimate.
  std::vector<char> touched_, touched_before_;
  FrameError frame_error_;         ///< the frame's summed local errors
  double iteration_errors_ = 0.0;  ///< m, the frame's substeps' iteration errors summed so far
  Points step_errors_;             ///< m, the substep's local errors (reused buffer)
  std::vector<char> estimated_;    ///< per particle, whether step_errors_ estimates it
};

}  // namespace cloth_sim
