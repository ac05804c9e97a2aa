/// @file simulation.h
/// One simulated object: model, state, pins, colliders and a solver, stepped together.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "cloth_sim/core/collision/colliders.h"
#include "cloth_sim/core/collision/self_contact.h"
#include "cloth_sim/core/collision/triangle_intersection.h"
#include "cloth_sim/core/model/model.h"
#include "cloth_sim/core/model/pins.h"
#include "cloth_sim/core/simulation/frame_inputs.h"
#include "cloth_sim/core/simulation/grasp.h"
#include "cloth_sim/core/simulation/grasp_set.h"
#include "cloth_sim/core/simulation/step_report.h"
#include "cloth_sim/core/simulation/step_controller.h"
#include "cloth_sim/core/simulation/substep.h"
#include "cloth_sim/core/solvers/midpoint_safeguard.h"
#include "cloth_sim/core/solvers/solver.h"

namespace cloth_sim {

/// Options fixed at construction (the solver, its settings and the frame time can be changed
/// later).
struct SimulationOptions {
  std::string solver = "local_global";  ///< a name from solverNames()
  SolverSettings settings;
  /// s of simulated time one Simulation::step advances (makeSimulation sets it from the scene's
  /// time_step); each of its SolverSettings::substeps implicit steps is frame_time / substeps.
  double frame_time = 1.0 / 60.0;
  /// Strain (|l - r| / r) above which a step is declared diverged and rolled back. The default
  /// 100 (10,000 %) is far above anything an implicit step reaches, even with a pin yanked 1 m
  /// across a 30-particle cloth, and is hit within a few steps by an unstable explicit solver.
  double divergence_strain = 100.0;
  /// Contact of the cloth with itself (off by default; docs/method.md, "Self-contact").
  SelfContactSettings self_contact;

  /// Throws std::invalid_argument naming the bad field (unknown solver, bad settings, ...).
  void validate() const;
};

/// A copy of every member of Simulation that carries over from one frame to the next
/// (Simulation::snapshot, Simulation::restore): restoring one and stepping gives the states of
/// the run it was taken from, bit for bit. What is not here is derived from what is (the movable
/// mask, the shortest rest length) or is not physics (the
/// factorization counter; the pose sources stay the simulation's own). The test
/// simulation/snapshot_test steps on after a restore and compares bit for bit on scenes with
/// contacts (spheres, balls, ground, meshes, bodies on frames), grasps, BDF2, warm start and
/// self-contact: a member added to Simulation and forgotten here fails it.
struct SimulationSnapshot {
  Model model;                  ///< stiffness and damping can change at run time
  State state;                  ///< positions, velocities, time and BDF2's previous step
  PinSet pins;                  ///< the pins with their targets (the grasps' included)
  Colliders colliders;          ///< spheres (velocities, spins), ground, meshes, bodies' poses
  SimulationOptions options;    ///< solver, its settings, frame time, self-contact
  FrameInputs inputs;           ///< where each pin target stood, pending sphere moves
  GraspSet grasps;              ///< held particles, their frame poses and wrenches
  SubstepPipeline substep;      ///< the contact forces' warm start
  std::vector<Vec3> pin_loads;  ///< N, the last substep's loads (the wrenches)
  /// The solver's warm start (Solver::carriedOver).
  SolverCarry solver_carry;
  int substeps = 0;                             ///< of the next frame (error control)
  StepController controller{1.0, 1, 1, 1};      ///< its calm frames towards a rung down
  /// Self-contact with its pair list (null when off); shared, as a snapshot never changes it.
  std::shared_ptr<const SelfContact> self_contact;
};

/// A mass-spring object with its pins and colliders, advanced one frame at a time.
///
/// Every editing method validates its input first and throws std::invalid_argument with a
/// message naming what is wrong, leaving the simulation untouched. An edit says what it changed
/// (a pin set, a stiffness, the step size, the integrator, a restart) and one function decides
/// from that what follows: a new revision, so that a factorizing solver refactors once at the
/// next step (pin set, stiffness, step size, integrator; moving a pin target or a sphere does
/// not), no BDF2 history (State::has_previous: pin set, step size, restart), the movable mask
/// and zero pin loads (pin set; loads also on a restart).
class Simulation {
 public:
  Simulation(Model model, const Points& rest_positions, PinSet pins, Colliders colliders,
             SimulationOptions options);

  /// Advances by one frame, frameTime() s, as SolverSettings::substeps implicit steps of
  /// substepTime(): in each, spheres move, the solver steps, contacts are resolved
  /// (SubstepPipeline). Pin targets and kinematic sphere centres the user moved since the last
  /// frame move there linearly across the substeps (FrameInputs: no jerk in the first
  /// substep). A non-finite or diverged frame is rolled back: the cloth and spheres return to
  /// what they were before the frame with every velocity set to zero, while the user's edits
  /// (pins, their targets, spheres and their moves) are kept; the report says so.
  StepReport step();

  /// Back to the initial state, pins and spheres given at construction, with no grasp.
  /// Stiffness, damping, h and solver keep their current values; the solver is made afresh and
  /// the contact warm start forgotten, so the same inputs after a reset give the same states bit
  /// for bit.
  void reset();
  /// The recovery from repeated divergence: the cloth back to its initial state (positions,
  /// zero velocities) and the dynamic spheres stopped, keeping every pin (with its target) and
  /// every sphere as it is now, so the user's edits survive. Each pin whose target is away from
  /// its particle's initial position is moved there across the next frame's substeps.
  void resetCloth();

  // --- snapshots ------------------------------------------------------------------------------
  /// Everything the next frame depends on (SimulationSnapshot).
  SimulationSnapshot snapshot() const;
  /// Back to @p snapshot (of this simulation or one built from the same scene: the same
  /// particle count, else std::invalid_argument and nothing changes). The next frames are those
  /// that followed the snapshot, bit for bit, given the same inputs (pose sources). The solver
  /// is made afresh and given the snapshot's warm start.
  void restore(const SimulationSnapshot& snapshot);
  /// Sets the particles' positions (m) and velocities (m/s), 3 x particleCount() each and
  /// finite, and the simulated time (s, finite and >= 0). BDF2's history and the contact warm
  /// start are forgotten (they belonged to the old state); pins, grasps and colliders stay.
  /// Throws std::invalid_argument naming the field, changing nothing.
  void setState(const Points& positions, const Points& velocities, double time);

  // --- run-time edits -------------------------------------------------------------------------
  /// Pins @p vertex at @p target (N/m stiffness, 0 = hard); returns the pin id.
  int addPin(int vertex, const Vec3& target, double stiffness = 0.0);
  /// Pins @p vertex where it is now.
  int addPinHere(int vertex, double stiffness = 0.0);
  /// Removes pin @p id; refused for a pin of a grasp (release the grasp instead).
  void removePin(int id);
  /// Sets pin @p id's target (m). The pin moves there across the next frame's substeps, at most
  /// maxPinMove() per frame: a target farther away is reached over several frames.
  /// Refused for a pin of a grasp (its frame moves it).
  void movePin(int id, const Vec3& target);
  /// Holds @p vertices (distinct, in range, not pinned yet, at least one) rigidly by a frame now
  /// at @p pose: each becomes a hard pin where it is now. From the next substep on, the targets
  /// follow the frame given by the pose source (setGraspPoseSource; without one, the frame stays
  /// at @p pose), rigidly and at the pins' speed limit: a held particle moves at most
  /// maxPinMove() per frame, so a frame that jumps is caught up with over several frames
  /// (Grasp::lag says how far behind). Returns the grasp id. Throws std::invalid_argument
  /// naming what is wrong.
  int addGrasp(const std::vector<int>& vertices, const Pose& pose);
  /// The grasp holding pin @p pin_id, or nullptr for a pin of the user's own.
  const Grasp* graspOf(int pin_id) const { return grasps_.graspOf(pin_id); }
  bool isGrasped(int pin_id) const { return graspOf(pin_id) != nullptr; }
  /// Lets go of grasp @p id: its pins are removed and its particles fall free.
  void removeGrasp(int id);
  /// The function asked, at each substep, where each grasp's frame is (empty: frames stay put).
  void setGraspPoseSource(GraspPoseSource source) { grasps_.setPoseSource(std::move(source)); }
  int addSphere(const SphereCollider& sphere) { return colliders_.addSphere(sphere); }
  void removeSphere(int id) { colliders_.removeSphere(id); }
  /// Sets sphere @p id to @p center (m) and @p velocity (m/s); a kinematic sphere goes there
  /// across the next frame's substeps, sweeping the cloth (FrameInputs::moveSphere).
  void moveSphere(int id, const Vec3& center, const Vec3& velocity);
  void setGround(const GroundPlane& ground) { colliders_.setGround(ground); }
  /// Adds a rigid body (BodySet::add: a sphere, capsule, box or mesh, still or following a
  /// frame); returns its id. Throws std::invalid_argument naming the bad field.
  int addBody(const BodyCollider& body) { return colliders_.mutableBodies().add(body); }
  /// Removes body @p id; throws std::invalid_argument for an unknown id.
  void removeBody(int id) { colliders_.mutableBodies().remove(id); }
  /// Puts body @p id's frame at @p frame_pose (simulation frame) now.
  void setBodyPose(int id, const Pose& frame_pose) {
    colliders_.mutableBodies().setFramePose(id, frame_pose);
  }
  /// The function asked, at each substep, where each body that follows a frame is (empty: they
  /// stay where they are).
  void setBodyPoseSource(BodyPoseSource source) { body_pose_source_ = std::move(source); }
  void setFamilyStiffness(SpringFamily family, double stiffness);
  /// Damping rate (1/s), see Model::damping. Does not refactor.
  void setDamping(double damping);
  /// Sets the frame time (s) that step() advances; the implicit step is h / substeps.
  void setTimeStep(double h);
  /// Switches solver (by name); the new one factorizes at its first step if it needs to.
  /// Throws if it does not support the current SolverSettings::integrator.
  void setSolver(const std::string& name);
  void setSolverSettings(const SolverSettings& settings);
  /// Turns self-contact on or off (and sets its thickness and friction); it acts from the next
  /// substep, and while on each step's report counts the intersecting triangle pairs. Throws
  /// std::invalid_argument naming the bad field; the automatic thickness is measured on the
  /// rest positions.
  void setSelfContact(const SelfContactSettings& settings);

  // --- read access ----------------------------------------------------------------------------
  const Model& model() const { return model_; }
  /// s of simulated time one step() advances: the scene's time_step
  /// (SimulationOptions::frame_time).
  double frameTime() const { return options_.frame_time; }
  /// Substeps of the next frame: SolverSettings::substeps, or with automatic substeps the error
  /// controller's choice.
  int substeps() const { return substeps_; }
  /// s, the implicit step h of each substep of the next frame: frameTime() / substeps().
  double substepTime() const { return options_.frame_time / substeps_; }
  /// The most substeps a frame may take with automatic substeps (a frame budget sets it; at
  /// most kMaxAutomaticSubsteps, at least 1). The reports say when the tolerance needs more.
  void setSubstepLimit(int max_substeps) {
    controller_.setMaxSubsteps(std::min(max_substeps, kMaxAutomaticSubsteps));
  }
  /// Wall-clock time (s) a frame may take before its work is cut (0: never, the default, which
  /// gives the same results on any machine). Past it, each solver stops iterating after its
  /// current iteration and the frame's remaining substeps run as one implicit Euler step to the
  /// frame's end (with self-contact on, as steps of about frame / kDeadlineSelfContactSteps);
  /// StepReport::cut_substeps and merged_substeps say so. The frame then takes about the
  /// deadline plus one substep of one iteration (with self-contact, up to
  /// kDeadlineSelfContactSteps steps of kDeadlineSelfContactIterations iterations and their
  /// self-contact), whatever the settings (the node's guard against a setting that would hold
  /// it for seconds). Throws for a negative or non-finite value.
  void setFrameDeadline(double seconds);
  double frameDeadline() const { return frame_deadline_; }
  /// The most substeps automatic substeps may take now (setSubstepLimit, else the cap).
  int substepLimit() const { return controller_.maxSubsteps(); }
  /// Automatic substeps: at most this many per frame...
  static constexpr int kMaxAutomaticSubsteps = 128;
  /// ... and this many at the first frame (the controller takes it from there).
  static constexpr int kFirstAutomaticSubsteps = 8;
  /// A frame whose error estimate is over this many times the tolerance is run again from its
  /// start with the substeps the controller then picks, as long as it picks more (automatic
  /// substeps, no self-contact, and not once a frame deadline cut the frame short). A
  /// controller that only chose the next frame kept the frame that showed the error: a sheet
  /// snapping off a sphere it started in kept 8 substeps at 400x the tolerance for its first
  /// frame and lost three quarters of its energy there.
  static constexpr double kRedoShare = 4.0;
  /// Past a frame deadline with self-contact on, the rest of the frame runs in steps of about
  /// frame / this (each n / this substeps merged, rounded up), not as one: one step over the
  /// rest of the frame handed self-contact the frame's whole motion at once (the `pile` scene
  /// at the default error control, a 50 ms deadline: frames of up to 47 s and rolled-back
  /// divergence, measured). The shipped self-contact scenes run 8 substeps a frame.
  static constexpr int kDeadlineSelfContactSteps = 8;
  /// ... of at least this many iterations each, as implicit Euler. With 2 (the shipped
  /// self-contact scenes' count) the cut pile gained energy frame after frame (4.7 J after 3 s
  /// at a 200 ms deadline, where its reference ends under 0.1 J), with 4 it rose 13 % over its
  /// start at a 50 ms deadline, with 6 never above its start at 50 or 200 ms (measured).
  static constexpr int kDeadlineSelfContactIterations = 6;
  /// Share of a substep's part of the frame's error tolerance (error_tolerance / substeps) its
  /// iterations may leave (SolverInput::iteration_tolerance); the rest is for truncation.
  static constexpr double kIterationShare = 0.5;
  const State& state() const { return state_; }
  /// m, the positions the simulation started from (and reset() returns to).
  const Points& initialPositions() const { return initial_state_.positions; }
  const PinSet& pins() const { return pins_; }
  /// What the cloth exerts on each pin (N) after the last substep, in pins().pins() order
  /// (PinReactions); zero after a pin-set change or a restart until the next step.
  const std::vector<Vec3>& pinLoads() const { return pin_loads_; }
  /// The grasps, in the order they were made; each with its pose and wrench of the last substep.
  const std::vector<Grasp>& grasps() const { return grasps_.grasps(); }
  /// The grasp with @p id, or nullptr.
  const Grasp* findGrasp(int id) const { return grasps_.find(id); }
  const Colliders& colliders() const { return colliders_; }
  /// The solver in use, by the name it was chosen with (the midpoint safeguard around it is
  /// not a solver of its own).
  const Solver& solver() const { return solver_->inner(); }
  const SolverSettings& solverSettings() const { return options_.settings; }
  const SimulationOptions& options() const { return options_; }
  /// Index of the particle nearest to @p point (m).
  int nearestParticle(const Vec3& point) const;
  /// Total energy (J): kinetic + springs + soft pins + gravity potential (zero at z = 0).
  double totalEnergy() const;
  /// The self-contact in use, or null when it is off.
  const SelfContact* selfContact() const { return self_contact_.get(); }
  /// Intersecting pairs of triangles sharing no vertex at the current positions (whether or not
  /// self-contact is on).
  int countIntersections();
  /// Numeric factorizations done by all solvers so far.
  int factorizationCount() const { return retired_factorizations_ + solver_->factorizationCount(); }
  /// The farthest a pin's target, or a grasp's held particle, moves in one frame (m): substeps x
  /// the shortest spring's rest length x divergence_strain / 10. A target set farther away, or a
  /// grasp frame moving faster, is approached at that speed.
  double maxPinMove() const;
  /// A speed limit on the pins' targets and the grasps' held particles (m/s; 0: none, the
  /// default): maxPinMove() is then at most this times the frame time. Throws for a negative or
  /// non-finite value.
  void setPinSpeedLimit(double metres_per_second);
  /// Bumped when h, a stiffness, a mass, the pin set or the integrator changes (see
  /// SolverInput::revision).
  std::uint64_t revision() const { return revision_; }

 private:
  /// What an edit changed, as bits of changed()'s argument.
  enum Change : unsigned {
    kPinSet = 1u << 0,      ///< pins added or removed, or their vertices or stiffness differ
    kStiffness = 1u << 1,   ///< a spring family's stiffness
    kControl = 1u << 2,     ///< the substeps or the error tolerance (SolverSettings)
    kIntegrator = 1u << 3,  ///< SolverSettings::integrator: another matrix
    kRestart = 1u << 4,     ///< the state was put back (rollback, reset, resetCloth)
  };
  /// Decides from @p changes (Change bits) what follows an edit: a new revision (pin set,
  /// stiffness, integrator), no BDF2 history (pin set: a new pin's particle has none on its
  /// target; restart), the movable mask (pin set), zero pin loads (pin set, restart), the
  /// substeps in use and their controller (control). A new step size needs nothing: BDF2 takes
  /// variable steps and the solvers keep a factor per step size.
  void changed(unsigned changes);
  /// Rolls the cloth and spheres back to @p state and @p colliders (zero velocities) and
  /// forgets the contact warm start that led there.
  void rollBack(const State& state, const Colliders& colliders);
  /// The parts of this simulation a substep works on.
  SubstepWorld substepWorld();
  /// One attempt at the frame step() runs, from @p before and @p colliders_before (the state
  /// and colliders at the frame's start; @p t0 its start time): the substeps, the rollback of
  /// a diverged frame and the controller's choice of the next substeps.
  StepReport runFrame(std::chrono::steady_clock::time_point t0, const State& before,
                      const Colliders& colliders_before);

  // Every member below that a frame carries over to the next is in SimulationSnapshot.
  Model model_;
  State state_, initial_state_;
  PinSet pins_, initial_pins_;
  Colliders colliders_, initial_colliders_;
  SimulationOptions options_;
  std::unique_ptr<MidpointSafeguard> solver_;  ///< the user's solver, in the safeguard
  int retired_factorizations_ = 0;
  std::uint64_t revision_ = 0;
  std::vector<char> movable_;  ///< false for hard-pinned particles (collisions skip them)
  std::unique_ptr<SelfContact> self_contact_;           ///< null when self-contact is off
  std::unique_ptr<IntersectionCounter> intersections_;  ///< built at first use
  double shortest_rest_length_ = 0.0;                   ///< m, of all springs (maxPinMove)
  FrameInputs inputs_;
  GraspSet grasps_;
  BodyPoseSource body_pose_source_;
  SubstepPipeline substep_;
  int substeps_ = 0;                     ///< of the next frame, see substeps()
  /// N, 3 x N: the self-contact pairs' pushes before a substep (FrameInputs::pinsAt).
  Points pushes_;
  StepController controller_{1.0, 1, 1, 1};  ///< automatic substeps (set up by changed)
  std::vector<Vec3> pin_loads_;  ///< N, see pinLoads()
  double frame_deadline_ = 0.0;  ///< s, setFrameDeadline (0: none); not physics, not snapshotted
  double pin_speed_limit_ = 0.0;  ///< m/s, setPinSpeedLimit (0: none)
};

}  // namespace cloth_sim
