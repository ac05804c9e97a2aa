#include "cloth_sim/core/model/pins.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "cloth_sim/core/settings/settings_table.h"

namespace cloth_sim {

int PinSet::add(int vertex, const Vec3& target, double stiffness, int particle_count) {
  if (vertex < 0 || vertex >= particle_count) {
    throw std::invalid_argument("pin vertex " + std::to_string(vertex) + " is out of range [0, " +
                                std::to_string(particle_count) + ")");
  }
  if (findByVertex(vertex) != nullptr) {
    throw std::invalid_argument("vertex " + std::to_string(vertex) + " is already pinned (pin " +
                                std::to_string(findByVertex(vertex)->id) + ")");
  }
  if (!target.allFinite()) throw std::invalid_argument("pin target must be finite");
  settings::kPinStiffness.require(stiffness, "pin stiffness");
  Pin p;
  p.id = next_id_++;
  p.vertex = vertex;
  p.target = target;
  p.stiffness = stiffness;
  pins_.push_back(p);
  return p.id;
}

void PinSet::remove(int id) {
  auto it = std::find_if(pins_.begin(), pins_.end(), [id](const Pin& p) { return p.id == id; });
  if (it == pins_.end()) throw std::invalid_argument("no pin with id " + std::to_string(id));
  pins_.erase(it);
}

void PinSet::moveTarget(int id, const Vec3& target) {
  if (!target.allFinite()) throw std::invalid_argument("pin target must be finite");
  auto it = std::find_if(pins_.begin(), pins_.end(), [id](const Pin& p) { return p.id == id; });
  if (it == pins_.end()) throw std::invalid_argument("no pin with id " + std::to_string(id));
  it->target = target;
}

const Pin* PinSet::find(int id) const {
  auto it = std::find_if(pins_.begin(), pins_.end(), [id](const Pin& p) { return p.id == id; });
  return it == pins_.end() ? nullptr : &*it;
}

const Pin* PinSet::findByVertex(int vertex) const {
  auto it = std::find_if(pins_.begin(), pins_.end(),
                         [vertex](const Pin& p) { return p.vertex == vertex; });
  return it == pins_.end() ? nullptr : &*it;
}

}  // namespace cloth_sim
