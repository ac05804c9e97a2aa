#include "cloth_sim/core/simulation/grasp_set.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

namespace cloth_sim {
namespace {

bool holds(const Grasp& g, int pin_id) {
  return std::find(g.pin_ids.begin(), g.pin_ids.end(), pin_id) != g.pin_ids.end();
}

}  // namespace

const Grasp* GraspSet::graspOf(int pin_id) const {
  for (const Grasp& g : grasps_) {
    if (holds(g, pin_id)) return &g;
  }
  return nullptr;
}

void GraspSet::requireNotGrasped(int pin_id, const char* what) const {
  if (const Grasp* g = graspOf(pin_id)) {
    throw std::invalid_argument("pin " + std::to_string(pin_id) + " belongs to grasp " +
                                std::to_string(g->id) + " and cannot be " + what +
                                " on its own (release the grasp)");
  }
}

const Grasp* GraspSet::find(int id) const {
  for (const Grasp& g : grasps_) {
    if (g.id == id) return &g;
  }
  return nullptr;
}

int GraspSet::add(const std::vector<int>& vertices, const Pose& pose, const Points& positions,
                  PinSet& pins) {
  if (vertices.empty()) throw std::invalid_argument("grasp: no particle to hold");
  if (!pose.matrix().allFinite())
    throw std::invalid_argument("grasp: the frame's pose is not finite");
  const int n = static_cast<int>(positions.cols());
  for (std::size_t k = 0; k < vertices.size(); ++k) {
    const int v = vertices[k];
    if (v < 0 || v >= n) {
      throw std::invalid_argument("grasp: vertex " + std::to_string(v) + " is out of range [0, " +
                                  std::to_string(n) + ")");
    }
    if (const Pin* pin = pins.findByVertex(v)) {
      throw std::invalid_argument("grasp: vertex " + std::to_string(v) +
                                  " is already pinned (pin " + std::to_string(pin->id) + ")");
    }
    for (std::size_t j = 0; j < k; ++j) {
      if (vertices[j] == v) {
        throw std::invalid_argument("grasp: vertex " + std::to_string(v) + " is listed twice");
      }
    }
  }
  // Checked above, so adding the pins cannot fail half way.
  Grasp g;
  g.id = next_id_++;
  g.vertices = vertices;
  g.pose = pose;
  g.local.resize(3, static_cast<Eigen::Index>(vertices.size()));
  const Pose to_local = pose.inverse();
  for (std::size_t k = 0; k < vertices.size(); ++k) {
    const Vec3 x = positions.col(vertices[k]);
    g.local.col(static_cast<Eigen::Index>(k)) = to_local * x;
    g.pin_ids.push_back(pins.add(vertices[k], x, 0.0, n));
  }
  grasps_.push_back(std::move(g));
  return grasps_.back().id;
}

void GraspSet::remove(int id, PinSet& pins) {
  auto it =
      std::find_if(grasps_.begin(), grasps_.end(), [id](const Grasp& g) { return g.id == id; });
  if (it == grasps_.end()) throw std::invalid_argument("no grasp with id " + std::to_string(id));
  for (int pin_id : it->pin_ids) pins.remove(pin_id);
  grasps_.erase(it);
}

void GraspSet::place(double time, PinSet& pins, PinSet* pins_at) {
  for (Grasp& g : grasps_) {
    if (pose_source_) {
      const Pose pose = pose_source_(g.id, time);
      if (pose.matrix().allFinite()) g.pose = pose;  // a bad answer keeps the last pose
    }
    for (std::size_t k = 0; k < g.pin_ids.size(); ++k) {
      const Vec3 target = g.pose * Vec3(g.local.col(static_cast<Eigen::Index>(k)));
      pins.moveTarget(g.pin_ids[k], target);
      if (pins_at != nullptr) pins_at->moveTarget(g.pin_ids[k], target);
    }
  }
}

void GraspSet::updateWrenches(const PinSet& pins, const std::vector<Vec3>& loads,
                              const Points& positions) {
  for (Grasp& g : grasps_) {
    g.wrench = Wrench();
    const Vec3 origin = g.pose.translation();
    for (std::size_t p = 0; p < pins.size(); ++p) {
      const Pin& pin = pins.pins()[p];
      if (!holds(g, pin.id)) continue;
      g.wrench.force += loads[p];
      g.wrench.torque += (Vec3(positions.col(pin.vertex)) - origin).cross(loads[p]);
    }
  }
}

}  // namespace cloth_sim
