#include "cloth_sim/core/simulation/simulation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <utility>

#include "cloth_sim/core/model/spring_kernels.h"
#include "cloth_sim/core/settings/settings_table.h"
#include "cloth_sim/core/solvers/implicit_euler_problem.h"

namespace cloth_sim {
namespace {

/// Whether @p a and @p b pin the same vertices with the same stiffness, in the same order: the
/// solvers' matrices are then the same.
bool samePinSet(const PinSet& a, const PinSet& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t k = 0; k < a.size(); ++k) {
    const Pin &p = a.pins()[k], &q = b.pins()[k];
    if (p.vertex != q.vertex || p.stiffness != q.stiffness) return false;
  }
  return true;
}

/// Stops every dynamic ball of @p colliders (velocity and spin); kinematic spheres keep theirs.
void stopDynamicSpheres(Colliders& colliders) {
  for (SphereCollider& s : colliders.mutableSpheres()) {
    if (!s.isDynamic()) continue;
    s.velocity.setZero();
    s.angular_velocity.setZero();
  }
}

}  // namespace

void SimulationOptions::validate() const {
  settings::kTimeStep.require(frame_time, "frame_time (the scene's time_step)");
  settings.validate();
  self_contact.validate();
  makeSolver(solver)->requireSettings(settings);  // makeSolver lists the names
  settings::kDivergenceStrain.require(divergence_strain);
}

Simulation::Simulation(Model model, const Points& rest_positions, PinSet pins, Colliders colliders,
                       SimulationOptions options)
    : model_(std::move(model)),
      pins_(std::move(pins)),
      colliders_(std::move(colliders)),
      options_(std::move(options)) {
  model_.validate();
  options_.validate();
  if (rest_positions.cols() != model_.particleCount() || !rest_positions.allFinite()) {
    throw std::invalid_argument("rest positions: need " + std::to_string(model_.particleCount()) +
                                " finite columns");
  }
  for (const Pin& p : pins_.pins()) {
    if (p.vertex >= model_.particleCount()) {
      throw std::invalid_argument("pin " + std::to_string(p.id) + ": vertex out of range");
    }
  }
  state_ = State::atRest(rest_positions);
  initial_state_ = state_;
  initial_pins_ = pins_;
  initial_colliders_ = colliders_;
  solver_ = std::make_unique<MidpointSafeguard>(makeSolver(options_.solver));
  const auto& rest = model_.springs.rest_length;
  shortest_rest_length_ = rest.empty() ? std::numeric_limits<double>::infinity()
                                       : *std::min_element(rest.begin(), rest.end());
  if (options_.self_contact.enabled) setSelfContact(options_.self_contact);
  changed(kPinSet | kControl);
  inputs_.startPinsAt(pins_, state_.positions);
}

void Simulation::changed(unsigned changes) {
  if ((changes & (kPinSet | kStiffness | kIntegrator)) != 0) ++revision_;
  if ((changes & (kPinSet | kRestart)) != 0) state_.has_previous = false;
  if ((changes & kRestart) != 0) controller_.restart();
  if ((changes & kControl) != 0) {
    const SolverSettings& s = options_.settings;
    if (s.automaticSubsteps()) {
      const int order = s.integrator == Integrator::kImplicitEuler ? 1 : 2;
      controller_ = StepController(s.error_tolerance, order, 1, kMaxAutomaticSubsteps);
      if (substeps_ < 1) substeps_ = kFirstAutomaticSubsteps;
    } else {
      substeps_ = s.substeps;
    }
  }
  if ((changes & kPinSet) != 0) {
    movable_.assign(model_.particleCount(), 1);
    for (const Pin& p : pins_.pins()) {
      if (p.isHard()) movable_[p.vertex] = 0;
    }
  }
  if ((changes & (kPinSet | kRestart)) != 0) pin_loads_.assign(pins_.size(), Vec3::Zero());
}

SubstepWorld Simulation::substepWorld() {
  return SubstepWorld{model_, options_.settings, movable_,  *solver_, self_contact_.get(),
                      state_, colliders_,        pin_loads_};
}

namespace {
const Points kNoPushes;  ///< FrameInputs::pinsAt without self-contact
}  // namespace

StepReport Simulation::step() {
  const auto t0 = std::chrono::steady_clock::now();
  const State before = state_;
  const Colliders colliders_before = colliders_;
  // What else a frame changes, kept to run it again when error control rejects it.
  struct FrameStart {
    PinSet pins;
    FrameInputs inputs;
    GraspSet grasps;
    SubstepPipeline substep;
    SolverCarry carry;
    std::vector<Vec3> pin_loads;
  };
  std::optional<FrameStart> start;
  if (options_.settings.automaticSubsteps() && !self_contact_) {
    start = FrameStart{pins_, inputs_, grasps_, substep_, solver_->carriedOver(), pin_loads_};
  }
  StepReport report = runFrame(t0, before, colliders_before);
  int rejected = 0;
  // Not once a deadline cut the frame short: the time for it is spent.
  while (start && report.status == StepStatus::kOk && !report.shortfall() &&
         substeps_ > report.substeps &&
         report.error_estimate > kRedoShare * report.error_tolerance) {
    rejected += report.substeps;
    state_ = before;
    colliders_ = colliders_before;
    pins_ = start->pins;
    inputs_ = start->inputs;
    grasps_ = start->grasps;
    substep_ = start->substep;
    solver_->carryOver(start->carry);
    pin_loads_ = start->pin_loads;
    controller_.restart();
    report = runFrame(t0, before, colliders_before);
  }
  report.rejected_substeps = rejected;
  grasps_.updateWrenches(pins_, pin_loads_, state_.positions);
  if (self_contact_) {
    const auto t_count = std::chrono::steady_clock::now();
    report.intersections = countIntersections();
    report.intersection_time =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t_count).count();
  }
  report.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return report;
}

StepReport Simulation::runFrame(std::chrono::steady_clock::time_point t0, const State& before,
                                const Colliders& colliders_before) {
  const int n = substeps_;
  const double h = substepTime();
  inputs_.beginFrame(pins_, maxPinMove(), options_.frame_time, colliders_);
  SubstepWorld world = substepWorld();
  if (frame_deadline_ > 0.0) {
    world.deadline = t0 + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                              std::chrono::duration<double>(frame_deadline_));
  }
  StepReport report;
  const double tolerance = options_.settings.error_tolerance;
  report.error_tolerance = tolerance;
  // Each substep's iterations stop at a share of its part of the frame's error tolerance.
  const double iteration_tolerance = kIterationShare * tolerance / n;
  const double frame_end = state_.time + options_.frame_time;
  substep_.beginFrame(model_.particleCount());
  for (int k = 1; k <= n; ++k) {
    double hk = h;
    int last = k;
    if (k > 1 && k < n && std::chrono::steady_clock::now() >= world.deadline) {
      // Past the deadline: the rest of the frame as one implicit step (stable, less accurate),
      // so that no setting holds the caller much longer than the deadline. With self-contact,
      // in steps of about a kDeadlineSelfContactSteps-th of the frame of a few iterations each
      // (one step, or one iteration, left the pushes after the solve to undo most of it: the
      // pile at the default with a 50 ms deadline diverged, measured).
      const int group =
          self_contact_ ? (n + kDeadlineSelfContactSteps - 1) / kDeadlineSelfContactSteps : n;
      if (self_contact_) world.min_iterations_at_deadline = kDeadlineSelfContactIterations;
      last = std::min(n, k + group - 1);
      hk = last == n ? frame_end - state_.time : (last - k + 1) * h;
      if (last > k) {
        report.merged_substeps += last - k + 1;
        // As implicit Euler: BDF2 over a step many times the one before (omega > 1 + sqrt 2)
        // is not zero-stable.
        state_.has_previous = false;
      }
    }
    // A grasp's frame is asked where it is at the end of each substep, so a moving gripper
    // carries the cloth continuously, not in one jump a frame. A hard pin moving this frame,
    // and a grasp, stop where the last substep's self-contact pairs push back (pinsAt).
    const bool pushed = self_contact_ && (!inputs_.paths().empty() || !grasps_.empty());
    if (pushed) {
      pushes_.setZero(3, model_.particleCount());
      substep_.contactForces().addSelfPushes(pushes_);
    }
    const PinSet& pins = inputs_.pinsAt(last, n, state_.time + hk, grasps_, pins_,
                                        pushed ? pushes_ : kNoPushes);
    colliders_.mutableBodies().place(state_.time + hk, body_pose_source_);  // bodies likewise
    substep_.run(world, pins, hk, revision_, iteration_tolerance, tolerance > 0.0, report);
    if (last == n) break;
    k = last;
  }
  if (tolerance > 0.0) report.error_estimate = substep_.frameErrorEstimate();
  report.max_strain = maxStrain(model_.springs, state_.positions);
  report.status = frameStatus(state_, colliders_, report.max_strain, options_.divergence_strain);
  const bool kept = report.status == StepStatus::kOk;
  if (!kept) {
    report.message = rollbackMessage(report.status, solver_->name(), report.max_strain,
                                     options_.divergence_strain, before.time);
    rollBack(before, colliders_before);
    report.max_strain = maxStrain(model_.springs, state_.positions);
  }
  inputs_.endFrame(kept, pins_, grasps_, options_.frame_time, colliders_);
  if (options_.settings.automaticSubsteps()) {
    // A rolled-back frame says its error was too large for its substeps.
    const double iterations =
        report.substeps > 0 ? double(report.total_iterations) / report.substeps : 0.0;
    const StepController::Decision next = controller_.next(
        n, kept ? report.error_estimate : std::numeric_limits<double>::infinity(), iterations);
    substeps_ = next.substeps;
    report.tolerance_unreachable = next.capped;
  }
  return report;
}

void Simulation::setFrameDeadline(double seconds) {
  if (!(std::isfinite(seconds) && seconds >= 0.0)) {
    throw std::invalid_argument("frame deadline " + std::to_string(seconds) +
                                " s must be finite and >= 0 (0 = none)");
  }
  frame_deadline_ = seconds;
}

double Simulation::maxPinMove() const {
  // A target jumping d in one implicit step stretches the springs of its particle by at most
  // d / r before the cloth follows: keeping that a tenth of divergence_strain keeps a drag,
  // however fast, far from a rolled-back frame.
  const double strain_bound = substeps_ * shortest_rest_length_ * options_.divergence_strain / 10.0;
  return pin_speed_limit_ > 0.0 ? std::min(strain_bound, pin_speed_limit_ * options_.frame_time)
                                : strain_bound;
}

void Simulation::setPinSpeedLimit(double metres_per_second) {
  if (!(std::isfinite(metres_per_second) && metres_per_second >= 0.0)) {
    throw std::invalid_argument("pin speed limit " + std::to_string(metres_per_second) +
                                " m/s must be finite and >= 0 (0 = none)");
  }
  pin_speed_limit_ = metres_per_second;
}

void Simulation::rollBack(const State& state, const Colliders& colliders) {
  state_ = state;
  state_.velocities.setZero();
  colliders_ = colliders;
  stopDynamicSpheres(colliders_);
  substep_.forgetContacts();  // forget the warm start that led there
  changed(kRestart);          // BDF2's next step is an implicit Euler step; no loads
}

void Simulation::reset() {
  state_ = initial_state_;
  // A fresh solver and warm start: nothing of the run before leaks into the one after.
  retired_factorizations_ += solver_->factorizationCount();
  solver_ = std::make_unique<MidpointSafeguard>(makeSolver(options_.solver));
  substep_.forgetContacts();
  grasps_.clear();
  const bool same_pins = samePinSet(pins_, initial_pins_);
  pins_ = initial_pins_;
  colliders_ = initial_colliders_;
  inputs_.startPinsAt(pins_, state_.positions);
  inputs_.clearSphereJumps();
  substeps_ = 0;  // automatic substeps start afresh too: the same run again, bit for bit
  changed(same_pins ? kRestart | kControl : kRestart | kControl | kPinSet);
}

void Simulation::resetCloth() {
  state_ = initial_state_;
  stopDynamicSpheres(colliders_);
  inputs_.clearSphereJumps();
  substep_.forgetContacts();  // forget the warm start that led to the divergence
  inputs_.startPinsAt(pins_, state_.positions);
  changed(kRestart);
}

int Simulation::addPin(int vertex, const Vec3& target, double stiffness) {
  const int id = pins_.add(vertex, target, stiffness, model_.particleCount());
  // The target is reached from where the particle is, at the pins' speed limit.
  inputs_.addPin(id, state_.positions.col(vertex));
  changed(kPinSet);
  return id;
}

int Simulation::addPinHere(int vertex, double stiffness) {
  if (vertex < 0 || vertex >= model_.particleCount()) {
    return addPin(vertex, Vec3::Zero(), stiffness);  // throws the range message
  }
  return addPin(vertex, state_.positions.col(vertex), stiffness);
}

void Simulation::removePin(int id) {
  grasps_.requireNotGrasped(id, "removed");
  pins_.remove(id);
  changed(kPinSet);
}

void Simulation::movePin(int id, const Vec3& target) {
  grasps_.requireNotGrasped(id, "moved");
  pins_.moveTarget(id, target);
}

int Simulation::addGrasp(const std::vector<int>& vertices, const Pose& pose) {
  const int id = grasps_.add(vertices, pose, state_.positions, pins_);
  changed(kPinSet);
  return id;
}

void Simulation::removeGrasp(int id) {
  grasps_.remove(id, pins_);
  changed(kPinSet);
}

void Simulation::moveSphere(int id, const Vec3& center, const Vec3& velocity) {
  inputs_.moveSphere(colliders_, id, center, velocity);
}

void Simulation::setFamilyStiffness(SpringFamily family, double stiffness) {
  stiffnessSetting(family).require(stiffness, std::string(springFamilyName(family)) + " stiffness");
  if (model_.familySize(family) == 0) {
    throw std::invalid_argument(std::string("this object has no ") + springFamilyName(family) +
                                " springs");
  }
  if (model_.familyStiffness(family) == stiffness) return;
  model_.setFamilyStiffness(family, stiffness);
  changed(kStiffness);
}

void Simulation::setDamping(double damping) {
  settings::kDamping.require(damping, "damping");
  model_.damping = damping;
}

void Simulation::setTimeStep(double h) {
  settings::kTimeStep.require(h, "time step");
  options_.frame_time = h;  // variable-step BDF2 and the kept factors follow a new step
}

void Simulation::setSolver(const std::string& name) {
  std::unique_ptr<Solver> next = makeSolver(name);
  next->requireSettings(options_.settings);
  retired_factorizations_ += solver_->factorizationCount();
  solver_ = std::make_unique<MidpointSafeguard>(std::move(next));
  options_.solver = name;
}

void Simulation::setSolverSettings(const SolverSettings& settings) {
  settings.validate();
  solver_->requireSettings(settings);
  unsigned changes = kControl;
  if (settings.integrator != options_.settings.integrator) changes |= kIntegrator;
  options_.settings = settings;
  changed(changes);
}

void Simulation::setSelfContact(const SelfContactSettings& settings) {
  settings.validate();
  std::unique_ptr<SelfContact> next;
  if (settings.enabled) {
    next = std::make_unique<SelfContact>(model_.triangles, initial_state_.positions, settings);
  }
  self_contact_ = std::move(next);
  options_.self_contact = settings;
}

int Simulation::countIntersections() {
  if (!intersections_) intersections_ = std::make_unique<IntersectionCounter>(model_.triangles);
  intersections_->setThreads(resolveThreads(options_.settings.threads));
  return intersections_->count(state_.positions);
}

int Simulation::nearestParticle(const Vec3& point) const {
  Eigen::Index best = 0;
  (state_.positions.colwise() - point).colwise().squaredNorm().minCoeff(&best);
  return static_cast<int>(best);
}

double Simulation::totalEnergy() const {
  return kineticEnergy(model_, state_) + springEnergy(model_.springs, state_.positions) +
         externalPotential(model_, pins_, state_.positions);
}

}  // namespace cloth_sim
