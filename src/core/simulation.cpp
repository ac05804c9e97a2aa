#include "cloth_sim/core/simulation.h"

#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "cloth_sim/core/solvers/implicit_euler_problem.h"
#include "cloth_sim/core/collision/sphere_impacts.h"
#include "cloth_sim/core/model/spring_kernels.h"

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
  makeSolver(solver);  // throws with the list of names
  settings.validate();
  if (!std::isfinite(divergence_strain) || divergence_strain <= 0.0) {
    throw std::invalid_argument("divergence_strain must be finite and > 0");
  }
}

Simulation::Simulation(Model model, const Points& rest_positions, PinSet pins,
                       Colliders colliders, SimulationOptions options)
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
  solver_ = makeSolver(options_.solver);
  rebuildMovableMask();
}

void Simulation::rebuildMovableMask() {
  movable_.assign(model_.particleCount(), 1);
  for (const Pin& p : pins_.pins()) {
    if (p.isHard()) movable_[p.vertex] = 0;
  }
}

StepReport Simulation::step() {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  const State before = state_;
  const Colliders colliders_before = colliders_;
  const double h = model_.time_step;

  colliders_.advance(h, model_.gravity, velocityDecay(model_));
  const CollisionStep collision{h, model_.mass, movable_, before.positions, &before.velocities,
                                model_.gravity};
  if (!colliders_.empty()) contacts_.beginStep(collision, colliders_);
  const SolverInput input{model_, pins_, revision_, colliders_.empty() ? nullptr : &contacts_};
  const auto t_solve = Clock::now();
  const SolveResult solved = solver_->step(input, options_.settings, state_);
  const auto t1 = Clock::now();

  StepReport report;
  report.iterations = solved.iterations;
  report.convergence = solved.convergence;
  report.converged = solved.converged;
  if (!colliders_.empty()) {
    // Only a solver that solved the contacts this step has fresh ball positions to hand over.
    if (solved.used_contacts) contacts_.finish(colliders_);
    report.contacts = resolveCollisions(collision, colliders_, state_.positions, state_.velocities,
                                        solved.used_contacts);
    report.contacts += resolveSphereImpacts(colliders_, 2.0 * model_.gravity.norm() * h);
  }
  report.max_strain = maxStrain(model_.springs, state_.positions);

  bool finite = state_.allFinite() && std::isfinite(report.max_strain);
  for (const SphereCollider& s : colliders_.spheres()) {
    finite = finite && s.center.allFinite() && s.velocity.allFinite() && s.angular_velocity.allFinite();
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
    state_ = before;
    state_.velocities.setZero();
    colliders_ = colliders_before;
    for (SphereCollider& s : colliders_.mutableSpheres()) {
      if (!s.isDynamic()) continue;
      s.velocity.setZero();
      s.angular_velocity.setZero();
    }
    contacts_ = ContactForces();  // forget the warm start that led there
    report.max_strain = maxStrain(model_.springs, state_.positions);
  }
  report.solve_time = std::chrono::duration<double>(t1 - t_solve).count();
  report.wall_time = std::chrono::duration<double>(Clock::now() - t0).count();
  return report;
}

void Simulation::reset() {
  state_ = initial_state_;
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
  rebuildMovableMask();
}

int Simulation::addPin(int vertex, const Vec3& target, double stiffness) {
  const int id = pins_.add(vertex, target, stiffness, model_.particleCount());
  ++revision_;
  rebuildMovableMask();
  return id;
}

int Simulation::addPinHere(int vertex, double stiffness) {
  if (vertex < 0 || vertex >= model_.particleCount()) {
    return addPin(vertex, Vec3::Zero(), stiffness);  // throws the range message
  }
  return addPin(vertex, state_.positions.col(vertex), stiffness);
}

void Simulation::removePin(int id) {
  pins_.remove(id);
  ++revision_;
  rebuildMovableMask();
}

void Simulation::movePin(int id, const Vec3& target) { pins_.moveTarget(id, target); }

int Simulation::addSphere(const SphereCollider& sphere) { return colliders_.addSphere(sphere); }

void Simulation::removeSphere(int id) { colliders_.removeSphere(id); }

void Simulation::moveSphere(int id, const Vec3& center, const Vec3& velocity) {
  colliders_.moveSphere(id, center, velocity);
}

void Simulation::setGround(const GroundPlane& ground) { colliders_.setGround(ground); }

void Simulation::setFamilyStiffness(SpringFamily family, double stiffness) {
  if (!std::isfinite(stiffness) || stiffness < 0.0) {
    throw std::invalid_argument(std::string(springFamilyName(family)) + " stiffness " +
                                std::to_string(stiffness) + " N/m must be finite and >= 0");
  }
  if (model_.familySize(family) == 0) {
    throw std::invalid_argument(std::string("this object has no ") + springFamilyName(family) +
                                " springs");
  }
  if (model_.familyStiffness(family) == stiffness) return;
  model_.setFamilyStiffness(family, stiffness);
  ++revision_;
}

void Simulation::setDamping(double damping) {
  if (!std::isfinite(damping) || damping < 0.0) {
    throw std::invalid_argument("damping " + std::to_string(damping) +
                                " 1/s must be finite and >= 0");
  }
  model_.damping = damping;
}

void Simulation::setTimeStep(double h) {
  if (!std::isfinite(h) || h <= 0.0) {
    throw std::invalid_argument("time step " + std::to_string(h) + " s must be finite and > 0");
  }
  if (h == model_.time_step) return;
  model_.time_step = h;
  ++revision_;
}

void Simulation::setSolver(const std::string& name) {
  std::unique_ptr<Solver> next = makeSolver(name);
  retired_factorizations_ += solver_->factorizationCount();
  solver_ = std::move(next);
  options_.solver = name;
}

void Simulation::setSolverSettings(const SolverSettings& settings) {
  settings.validate();
  options_.settings = settings;
}

int Simulation::nearestParticle(const Vec3& point) const {
  Eigen::Index best = 0;
  (state_.positions.colwise() - point).colwise().squaredNorm().minCoeff(&best);
  return static_cast<int>(best);
}

double Simulation::totalEnergy() const {
  const double kinetic =
      0.5 * (state_.velocities.colwise().squaredNorm() * model_.mass)(0);
  return kinetic + springEnergy(model_.springs, state_.positions) +
         externalPotential(model_, pins_, state_.positions);
}

int Simulation::factorizationCount() const {
  return retired_factorizations_ + solver_->factorizationCount();
}

}  // namespace cloth_sim
