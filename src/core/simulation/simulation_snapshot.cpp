// Simulation's snapshots: save and restore everything the next frame depends on
// (SimulationSnapshot), and set the particles' state.
#include <stdexcept>
#include <string>

#include "cloth_sim/core/settings/settings_table.h"
#include "cloth_sim/core/simulation/simulation.h"

namespace cloth_sim {
namespace {

/// Throws unless @p p is 3 x @p n and finite, naming @p what.
void requireParticles(const Points& p, int n, const char* what) {
  if (p.cols() != n) {
    throw std::invalid_argument(std::string(what) + ": " + std::to_string(p.cols()) +
                                " particles given, the cloth has " + std::to_string(n));
  }
  if (!p.allFinite()) throw std::invalid_argument(std::string(what) + " must be finite");
}

}  // namespace

SimulationSnapshot Simulation::snapshot() const {
  return SimulationSnapshot{model_,   state_,   pins_,      colliders_,
                            options_, inputs_,  grasps_,    substep_,
                            pin_loads_, solver_->carriedOver(), substeps_, controller_,
                            self_contact_ ? std::make_shared<const SelfContact>(*self_contact_)
                                          : nullptr};
}

void Simulation::restore(const SimulationSnapshot& s) {
  if (s.model.particleCount() != model_.particleCount() ||
      s.state.positions.cols() != model_.particleCount()) {
    throw std::invalid_argument("snapshot of " + std::to_string(s.model.particleCount()) +
                                " particles, the cloth has " +
                                std::to_string(model_.particleCount()));
  }
  s.options.validate();
  // Built before anything changes: a throw leaves the simulation as it was.
  auto solver = std::make_unique<MidpointSafeguard>(makeSolver(s.options.solver));
  std::unique_ptr<SelfContact> self_contact;
  if (s.self_contact) {
    self_contact = std::make_unique<SelfContact>(*s.self_contact);
  } else if (s.options.self_contact.enabled) {
    self_contact = std::make_unique<SelfContact>(s.model.triangles, initial_state_.positions,
                                                 s.options.self_contact);
  }
  const GraspPoseSource grasp_source = grasps_.poseSource();
  model_ = s.model;
  pins_ = s.pins;
  colliders_ = s.colliders;
  options_ = s.options;
  inputs_ = s.inputs;
  grasps_ = s.grasps;
  grasps_.setPoseSource(grasp_source);
  substep_ = s.substep;
  retired_factorizations_ += solver_->factorizationCount();
  solver_ = std::move(solver);
  solver_->carryOver(s.solver_carry);
  self_contact_ = std::move(self_contact);
  changed(kPinSet);  // a new revision (the fresh solver factors anyway) and the movable mask
  state_ = s.state;  // after changed(): BDF2's history is the snapshot's
  pin_loads_ = s.pin_loads;
  substeps_ = s.substeps;  // error control goes on from where it was
  controller_ = s.controller;
}

void Simulation::setState(const Points& positions, const Points& velocities, double time) {
  const int n = model_.particleCount();
  requireParticles(positions, n, "positions");
  requireParticles(velocities, n, "velocities");
  settings::kCoordinate.require(positions.cwiseAbs().maxCoeff(), "positions: largest coordinate");
  settings::kSimTime.require(time, "time");
  state_.positions = positions;
  state_.velocities = velocities;
  state_.time = time;
  substep_.forgetContacts();  // the warm start belonged to the old state
  changed(kRestart);          // and so did BDF2's history
}

}  // namespace cloth_sim
