#include "cloth_sim/core/simulation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "cloth_sim/core/collision/sphere_impacts.h"
#include "cloth_sim/core/model/spring_kernels.h"
#include "cloth_sim/core/settings/settings_table.h"
#include "cloth_sim/core/solvers/implicit_euler_problem.h"

namespace cloth_sim {

const char* stepStatusName(StepStatus status) {
  switch (status) {
    case StepStatus::kOk: return "ok";
    case StepStatus::kNonFinite: return "non_finite";
    case StepStatus::kDiverged: return "diverged";
  }
  return "unknown";
}

void SimulationOptions::validate() const {
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
  frame_time_ = model_.time_step;
  model_.time_step = frame_time_ / options_.settings.substeps;
  state_ = State::atRest(rest_positions);
  initial_state_ = state_;
  initial_pins_ = pins_;
  initial_colliders_ = colliders_;
  solver_ = makeSolver(options_.solver);
  rebuildMovableMask();
  const auto& rest = model_.springs.rest_length;
  shortest_rest_length_ = rest.empty() ? std::numeric_limits<double>::infinity()
                                       : *std::min_element(rest.begin(), rest.end());
  if (options_.self_contact.enabled) setSelfContact(options_.self_contact);
  clearLoads();
  startPinsAtParticles();
}

void Simulation::startPinsAtParticles() {
  frame_targets_.clear();
  for (const Pin& pin : pins_.pins()) {
    frame_targets_.emplace_back(pin.id, Vec3(state_.positions.col(pin.vertex)));
  }
}

void Simulation::rebuildMovableMask() {
  movable_.assign(model_.particleCount(), 1);
  for (const Pin& p : pins_.pins()) {
    if (p.isHard()) movable_[p.vertex] = 0;
  }
}

StepReport Simulation::step() {
  const auto t0 = std::chrono::steady_clock::now();
  const State before = state_;
  const Colliders colliders_before = colliders_;
  const int n = options_.settings.substeps;
  std::vector<PinPath> paths;  // the pins whose target moved since the last frame
  for (const auto& [id, from] : frame_targets_) {
    const Pin* pin = pins_.find(id);
    if (pin != nullptr && pin->target != from) paths.push_back({id, from, towards(from, pin->target)});
  }
  const bool pins_moved = !paths.empty();
  PinSet pins_at = pins_moved ? pins_ : PinSet();
  applySphereJumps(+1.0);
  std::vector<std::pair<int, Vec3>> frame_end;  // where each target stands when the frame ends
  for (const Pin& pin : pins_.pins()) frame_end.emplace_back(pin.id, pin.target);
  for (const PinPath& path : paths) {
    for (auto& [id, target] : frame_end) {
      if (id == path.id) target = path.to;
    }
  }
  StepReport report;
  for (int k = 1; k <= n; ++k) {
    if (pins_moved) interpolatePins(static_cast<double>(k) / n, paths, pins_at);
    // A grasp's frame is asked where it is at the end of each substep, so a moving gripper
    // carries the cloth continuously, not in one jump a frame.
    if (!grasps_.empty()) placeGrasps(state_.time + model_.time_step, pins_moved ? &pins_at : nullptr);
    substep(pins_moved ? pins_at : pins_, report);
  }
  report.max_strain = maxStrain(model_.springs, state_.positions);

  bool finite = state_.allFinite() && std::isfinite(report.max_strain);
  for (const SphereCollider& s : colliders_.spheres()) {
    finite =
        finite && s.center.allFinite() && s.velocity.allFinite() && s.angular_velocity.allFinite();
  }
  if (!finite || report.max_strain > options_.divergence_strain) {
    std::ostringstream msg;
    report.status = finite ? StepStatus::kDiverged : StepStatus::kNonFinite;
    if (finite) {
      msg << solver_->name() << " diverged: max strain " << report.max_strain << " > limit "
          << options_.divergence_strain;
    } else {
      msg << solver_->name() << " produced a non-finite position or velocity";
    }
    msg << " at t = " << before.time << " s; rolled back to that state with zero velocities"
        << " (cloth and dynamic spheres)";
    report.message = msg.str();
    rollBack(before, colliders_before);
    clearLoads();
    report.max_strain = maxStrain(model_.springs, state_.positions);
  } else {
    applySphereJumps(-1.0);
  }
  updateGraspWrenches();
  sphere_jumps_.clear();
  // A grasp's pins follow its frame (placeGrasps), not the speed limit of the user's moves.
  for (auto& [id, target] : frame_end) {
    if (isGrasped(id)) target = pins_.find(id)->target;
  }
  frame_targets_ = std::move(frame_end);
  if (self_contact_) {
    const auto t_count = std::chrono::steady_clock::now();
    report.intersections = countIntersections();
    report.intersection_time =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t_count).count();
  }
  report.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return report;
}

void Simulation::substep(const PinSet& pins, StepReport& report) {
  const double h = model_.time_step;
  const bool loads = !pins.empty();
  if (loads) reactions_.begin(model_, pins, state_, options_.settings.integrator);
  if (colliders_.empty() && !self_contact_) {  // nothing to collide with: no start state to keep
    solve(SolverInput{model_, pins, revision_, nullptr}, report);
    if (loads) reactions_.finish(model_, pins, state_.positions, pin_loads_);
    return;
  }
  const Points start = state_.positions, start_velocities = state_.velocities;
  colliders_.advance(h, model_.gravity, velocityDecay(model_));
  const CollisionStep collision{h, model_.mass, movable_, start, &start_velocities, model_.gravity};
  contacts_.beginStep(collision, colliders_);
  const SolveResult solved = solve(SolverInput{model_, pins, revision_, &contacts_}, report);
  // The loads of the solve itself, before the collision response moves soft-pinned particles.
  if (loads) reactions_.finish(model_, pins, state_.positions, pin_loads_);
  // Only a solver that solved the contacts this step has fresh ball positions to hand over.
  if (solved.used_contacts) {
    contacts_.finish(colliders_);
    report.contacts += contacts_.activeCount();
  }
  const auto t_self = std::chrono::steady_clock::now();
  // The bound before the colliders: a collider's own correction is never shortened.
  if (self_contact_) {
    report.self_contacts +=
        self_contact_->limitDisplacement(collision, state_.positions, state_.velocities);
  }
  auto self_time = std::chrono::steady_clock::now() - t_self;
  report.contacts += resolveCollisions(collision, colliders_, state_.positions, state_.velocities,
                                       solved.used_contacts);
  report.contacts += resolveSphereImpacts(colliders_, 2.0 * model_.gravity.norm() * h);
  if (self_contact_) {
    const auto t_resolve = std::chrono::steady_clock::now();
    report.self_contacts += self_contact_->resolve(collision, colliders_.ground(), state_.positions,
                                                   state_.velocities);
    self_time += std::chrono::steady_clock::now() - t_resolve;
    report.self_contact_time += std::chrono::duration<double>(self_time).count();
  }
}

namespace {

/// Kinetic energy 1/2 v^T M v of @p state (J).
double kineticEnergy(const Model& model, const State& state) {
  return 0.5 * (state.velocities.colwise().squaredNorm() * model.mass)(0);
}

/// Energies of a state (J) for the midpoint safeguard.
struct StateEnergy {
  double mechanical;  ///< kinetic + springs
  double total;       ///< mechanical + gravity and soft pins
};

/// The energy of @p state as Simulation::totalEnergy, but without the hard-pinned particles'
/// kinetic energy: their velocity is prescribed (a pin teleported by 1 m in one step moves at
/// 1 m / h), not energy the cloth can use.
StateEnergy stateEnergy(const Model& model, const PinSet& pins, const State& state) {
  double kinetic = kineticEnergy(model, state);
  for (const Pin& pin : pins.pins()) {
    if (pin.isHard())
      kinetic -= 0.5 * model.mass[pin.vertex] * state.velocities.col(pin.vertex).squaredNorm();
  }
  const double mechanical = kinetic + springEnergy(model.springs, state.positions);
  return {mechanical, mechanical + externalPotential(model, pins, state.positions)};
}

/// The implicit midpoint safeguard's tolerance: a step may gain this fraction of the kinetic
/// plus spring energy at its start (J / J), plus kMidpointGainFloor times m |g| (J / N, i.e.
/// m) so that a cloth released at rest is not held to its exact energy.
constexpr double kMidpointGain = 1e-2;
constexpr double kMidpointGainFloor = 1e-4;

}  // namespace

SolveResult Simulation::solve(const SolverInput& input, StepReport& report) {
  const auto t_solve = std::chrono::steady_clock::now();
  if (options_.settings.integrator != Integrator::kImplicitMidpoint) {
    const SolveResult solved = solver_->step(input, options_.settings, state_);
    return finishSolve(solved, t_solve, report);
  }
  // Implicit midpoint safeguard. Without moving pins the energy of a step cannot grow (the
  // damping only removes it); a converged midpoint step keeps it to O(h^2) and an
  // under-iterated one loses some. Plain midpoint on stiff cloth at large steps gains energy
  // step after step until it explodes (benchmark.md, "Stability"): a step that gains more than
  // the tolerance is redone as two implicit Euler steps of h/2. A growth slower than the
  // tolerance per step is not caught (kept as measured: a running budget caught it, but also
  // fired on the peers' cloth and cost it most of its energy).
  const State before = state_;
  const StateEnergy energy_before = stateEnergy(input.model, input.pins, state_);
  SolveResult solved = solver_->step(input, options_.settings, state_);
  const double allowed = kMidpointGain * energy_before.mechanical +
                         kMidpointGainFloor * input.model.mass.sum() * input.model.gravity.norm();
  if (stateEnergy(input.model, input.pins, state_).total - energy_before.total > allowed) {
    // Two implicit Euler steps of h/2: their matrix is the midpoint's, M + (h/2)^2 L (same
    // revision and h_i, so no refactorization), and implicit Euler is L-stable. Contacts are
    // left to the projection after the step, as under midpoint.
    state_ = before;
    SolverSettings euler = options_.settings;
    euler.integrator = Integrator::kImplicitEuler;
    const double h = model_.time_step;
    model_.time_step = 0.5 * h;
    const SolverInput half{model_, input.pins, input.revision, nullptr};
    solver_->step(half, euler, state_);
    solved = solver_->step(half, euler, state_);
    model_.time_step = h;
    state_.time = before.time + h;
    ++report.midpoint_fallbacks;
  }
  return finishSolve(solved, t_solve, report);
}

SolveResult Simulation::finishSolve(const SolveResult& solved,
                                    std::chrono::steady_clock::time_point t_solve,
                                    StepReport& report) {
  report.solve_time +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_solve).count();
  ++report.substeps;
  report.iterations = solved.iterations;
  report.convergence = solved.convergence;
  report.converged = solved.converged;
  return solved;
}

void Simulation::interpolatePins(double s, const std::vector<PinPath>& paths,
                                 PinSet& pins_at) const {
  for (const PinPath& path : paths) pins_at.moveTarget(path.id, path.from + s * (path.to - path.from));
}

double Simulation::maxPinMove() const {
  // A target jumping d in one implicit step stretches the springs of its particle by at most
  // d / r before the cloth follows: keeping that a tenth of divergence_strain keeps a drag,
  // however fast, far from a rolled-back frame.
  return options_.settings.substeps * shortest_rest_length_ * options_.divergence_strain / 10.0;
}

Vec3 Simulation::towards(const Vec3& from, const Vec3& target) const {
  const Vec3 way = target - from;
  const double distance = way.norm(), limit = maxPinMove();
  return distance <= limit ? target : Vec3(from + way * (limit / distance));
}

void Simulation::applySphereJumps(double sign) {
  for (const SphereJump& jump : sphere_jumps_) {
    const SphereCollider* s = colliders_.findSphere(jump.id);
    if (s == nullptr) continue;
    colliders_.moveSphere(jump.id, s->center, s->velocity + sign * jump.displacement / frame_time_);
  }
}

void Simulation::rollBack(const State& state, const Colliders& colliders) {
  state_ = state;
  state_.velocities.setZero();
  state_.has_previous = false;  // a restart: BDF2's next step is an implicit Euler step
  colliders_ = colliders;
  for (SphereCollider& s : colliders_.mutableSpheres()) {
    if (!s.isDynamic()) continue;
    s.velocity.setZero();
    s.angular_velocity.setZero();
  }
  // The user's sphere moves of this frame stand: those spheres go where they were sent.
  for (const SphereJump& jump : sphere_jumps_) {
    if (const SphereCollider* s = colliders_.findSphere(jump.id)) {
      colliders_.moveSphere(jump.id, s->center + jump.displacement, s->velocity);
    }
  }
  contacts_ = ContactForces();  // forget the warm start that led there
}

void Simulation::reset() {
  state_ = initial_state_;
  // A fresh solver and warm start: nothing of the run before leaks into the one after.
  retired_factorizations_ += solver_->factorizationCount();
  solver_ = makeSolver(options_.solver);
  contacts_ = ContactForces();
  grasps_.clear();
  if (pins_.size() != initial_pins_.size()) ++revision_;
  else {
    for (std::size_t k = 0; k < pins_.size(); ++k) {
      const Pin &a = pins_.pins()[k], &b = initial_pins_.pins()[k];
      if (a.vertex != b.vertex || a.stiffness != b.stiffness) {
        ++revision_;
        break;
      }
    }
  }
  pins_ = initial_pins_;
  colliders_ = initial_colliders_;
  startPinsAtParticles();
  sphere_jumps_.clear();
  rebuildMovableMask();
  clearLoads();
}

void Simulation::resetCloth() {
  state_ = initial_state_;
  for (SphereCollider& s : colliders_.mutableSpheres()) {
    if (!s.isDynamic()) continue;
    s.velocity.setZero();
    s.angular_velocity.setZero();
  }
  sphere_jumps_.clear();
  contacts_ = ContactForces();  // forget the warm start that led to the divergence
  startPinsAtParticles();
}

int Simulation::addPin(int vertex, const Vec3& target, double stiffness) {
  const int id = pins_.add(vertex, target, stiffness, model_.particleCount());
  // The target is reached from where the particle is, at the pins' speed limit.
  frame_targets_.emplace_back(id, Vec3(state_.positions.col(vertex)));
  ++revision_;
  state_.has_previous = false;  // the new pin's particle has no BDF2 history on its target
  rebuildMovableMask();
  clearLoads();
  return id;
}

int Simulation::addPinHere(int vertex, double stiffness) {
  if (vertex < 0 || vertex >= model_.particleCount()) {
    return addPin(vertex, Vec3::Zero(), stiffness);  // throws the range message
  }
  return addPin(vertex, state_.positions.col(vertex), stiffness);
}

void Simulation::removePin(int id) {
  requireNotGrasped(id, "removed");
  pins_.remove(id);
  ++revision_;
  state_.has_previous = false;
  rebuildMovableMask();
  clearLoads();
}

void Simulation::movePin(int id, const Vec3& target) {
  requireNotGrasped(id, "moved");
  pins_.moveTarget(id, target);
}

int Simulation::addSphere(const SphereCollider& sphere) { return colliders_.addSphere(sphere); }

void Simulation::removeSphere(int id) { colliders_.removeSphere(id); }

void Simulation::moveSphere(int id, const Vec3& center, const Vec3& velocity) {
  const SphereCollider* s = colliders_.findSphere(id);
  const Vec3 from = s != nullptr ? s->center : center;
  colliders_.moveSphere(id, center, velocity);         // validates; throws for an unknown id
  if (colliders_.findSphere(id)->isDynamic()) return;  // a ball is placed at once
  // A kinematic sphere goes there across the next frame's substeps, sweeping the cloth.
  colliders_.moveSphere(id, from, velocity);
  for (SphereJump& jump : sphere_jumps_) {
    if (jump.id == id) {
      jump.displacement = center - from;
      return;
    }
  }
  sphere_jumps_.push_back({id, center - from});
}

void Simulation::setGround(const GroundPlane& ground) { colliders_.setGround(ground); }

void Simulation::setFamilyStiffness(SpringFamily family, double stiffness) {
  stiffnessSetting(family).require(stiffness, std::string(springFamilyName(family)) + " stiffness");
  if (model_.familySize(family) == 0) {
    throw std::invalid_argument(std::string("this object has no ") + springFamilyName(family) +
                                " springs");
  }
  if (model_.familyStiffness(family) == stiffness) return;
  model_.setFamilyStiffness(family, stiffness);
  ++revision_;
}

void Simulation::setDamping(double damping) {
  settings::kDamping.require(damping, "damping");
  model_.damping = damping;
}

void Simulation::setTimeStep(double h) {
  settings::kTimeStep.require(h, "time step");
  if (h == frame_time_) return;
  frame_time_ = h;
  model_.time_step = h / options_.settings.substeps;
  ++revision_;
  state_.has_previous = false;  // BDF2's history is for the old step
}

void Simulation::setSolver(const std::string& name) {
  std::unique_ptr<Solver> next = makeSolver(name);
  next->requireSettings(options_.settings);
  retired_factorizations_ += solver_->factorizationCount();
  solver_ = std::move(next);
  options_.solver = name;
}

void Simulation::setSolverSettings(const SolverSettings& settings) {
  settings.validate();
  solver_->requireSettings(settings);
  if (settings.substeps != options_.settings.substeps) {
    model_.time_step = frame_time_ / settings.substeps;
    ++revision_;
    state_.has_previous = false;
  }
  if (settings.integrator != options_.settings.integrator) ++revision_;  // another matrix
  options_.settings = settings;
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

int Simulation::factorizationCount() const {
  return retired_factorizations_ + solver_->factorizationCount();
}

}  // namespace cloth_sim

// --- grasps ----------------------------------------------------------------------------------
namespace cloth_sim {

void Simulation::clearLoads() { pin_loads_.assign(pins_.size(), Vec3::Zero()); }

const Grasp* Simulation::graspOf(int pin_id) const {
  for (const Grasp& g : grasps_) {
    if (std::find(g.pin_ids.begin(), g.pin_ids.end(), pin_id) != g.pin_ids.end()) return &g;
  }
  return nullptr;
}

void Simulation::requireNotGrasped(int id, const char* what) const {
  if (const Grasp* g = graspOf(id)) {
    throw std::invalid_argument("pin " + std::to_string(id) + " belongs to grasp " +
                                std::to_string(g->id) + " and cannot be " + what +
                                " on its own (release the grasp)");
  }
}

const Grasp* Simulation::findGrasp(int id) const {
  for (const Grasp& g : grasps_) {
    if (g.id == id) return &g;
  }
  return nullptr;
}

int Simulation::addGrasp(const std::vector<int>& vertices, const Pose& pose) {
  if (vertices.empty()) throw std::invalid_argument("grasp: no particle to hold");
  if (!pose.matrix().allFinite()) throw std::invalid_argument("grasp: the frame's pose is not finite");
  const int n = model_.particleCount();
  for (std::size_t k = 0; k < vertices.size(); ++k) {
    const int v = vertices[k];
    if (v < 0 || v >= n) {
      throw std::invalid_argument("grasp: vertex " + std::to_string(v) + " is out of range [0, " +
                                  std::to_string(n) + ")");
    }
    if (const Pin* pin = pins_.findByVertex(v)) {
      throw std::invalid_argument("grasp: vertex " + std::to_string(v) + " is already pinned (pin " +
                                  std::to_string(pin->id) + ")");
    }
    for (std::size_t j = 0; j < k; ++j) {
      if (vertices[j] == v) {
        throw std::invalid_argument("grasp: vertex " + std::to_string(v) + " is listed twice");
      }
    }
  }
  // Checked above, so adding the pins cannot fail half way.
  Grasp g;
  g.id = next_grasp_id_++;
  g.vertices = vertices;
  g.pose = pose;
  g.local.resize(3, static_cast<Eigen::Index>(vertices.size()));
  const Pose to_local = pose.inverse();
  for (std::size_t k = 0; k < vertices.size(); ++k) {
    const Vec3 x = state_.positions.col(vertices[k]);
    g.local.col(static_cast<Eigen::Index>(k)) = to_local * x;
    g.pin_ids.push_back(pins_.add(vertices[k], x, 0.0, n));
  }
  grasps_.push_back(std::move(g));
  ++revision_;
  state_.has_previous = false;
  rebuildMovableMask();
  clearLoads();
  return grasps_.back().id;
}

void Simulation::removeGrasp(int id) {
  auto it = std::find_if(grasps_.begin(), grasps_.end(), [id](const Grasp& g) { return g.id == id; });
  if (it == grasps_.end()) throw std::invalid_argument("no grasp with id " + std::to_string(id));
  for (int pin_id : it->pin_ids) pins_.remove(pin_id);
  grasps_.erase(it);
  ++revision_;
  state_.has_previous = false;
  rebuildMovableMask();
  clearLoads();
}

void Simulation::placeGrasps(double time, PinSet* pins_at) {
  for (Grasp& g : grasps_) {
    if (pose_source_) {
      const Pose pose = pose_source_(g.id, time);
      if (pose.matrix().allFinite()) g.pose = pose;  // a bad answer keeps the last pose
    }
    for (std::size_t k = 0; k < g.pin_ids.size(); ++k) {
      const Vec3 target = g.pose * Vec3(g.local.col(static_cast<Eigen::Index>(k)));
      pins_.moveTarget(g.pin_ids[k], target);
      if (pins_at != nullptr) pins_at->moveTarget(g.pin_ids[k], target);
    }
  }
}

void Simulation::updateGraspWrenches() {
  for (Grasp& g : grasps_) {
    g.wrench = Wrench();
    const Vec3 origin = g.pose.translation();
    for (std::size_t p = 0; p < pins_.size(); ++p) {
      const Pin& pin = pins_.pins()[p];
      if (std::find(g.pin_ids.begin(), g.pin_ids.end(), pin.id) == g.pin_ids.end()) continue;
      g.wrench.force += pin_loads_[p];
      g.wrench.torque += (Vec3(state_.positions.col(pin.vertex)) - origin).cross(pin_loads_[p]);
    }
  }
}

}  // namespace cloth_sim
