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

/// The farthest any of @p local (in the grasp frame) moves from @p from to @p to (m).
double farthestMove(const Pose& from, const Pose& to, const Points& local) {
  double farthest = 0.0;
  for (Eigen::Index k = 0; k < local.cols(); ++k) {
    const Vec3 l = local.col(k);
    farthest = std::max(farthest, (to * l - from * l).norm());
  }
  return farthest;
}

/// @p from moved rigidly towards @p to with no held particle (@p local) moving more than
/// @p limit m: @p to itself when none moves farther; else a fraction of the way, the held
/// particles' centre moving along the straight line and the turn about it slerped.
Pose towards(const Pose& from, const Pose& to, const Points& local, double limit) {
  const double full = farthestMove(from, to, local);
  // Within the limit, or over it by no more than the rounding of the moves before: there.
  if (full <= limit * (1.0 + 1e-9)) return to;
  const Vec3 centre = from * Vec3(local.rowwise().mean());
  const Pose delta = to * from.inverse();  // the whole move, in the simulation frame
  const Eigen::Quaterniond turn(delta.linear());
  const Vec3 shift = delta * centre - centre;
  const auto at = [&](double s) {
    Pose part = Pose::Identity();
    part.translate(centre + s * shift);
    part.rotate(Eigen::Quaterniond::Identity().slerp(s, turn));
    part.translate(-centre);
    return Pose(part * from);
  };
  // A turn moves a particle along an arc, farther at a fraction s than s times its whole move's
  // chord: s shrinks until the farthest move is within the limit.
  double s = limit / full;
  Pose pose = at(s);
  for (int i = 0; i < 8; ++i) {
    const double moved = farthestMove(from, pose, local);
    if (moved <= limit) break;
    s *= limit / moved;
    pose = at(s);
  }
  return pose;
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
  g.frame = pose;
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

void GraspSet::place(double time, double max_move, PinSet& pins, PinSet* pins_at,
                     const Points& pushes) {
  for (Grasp& g : grasps_) {
    if (pose_source_) {
      const Pose pose = pose_source_(g.id, time);
      if (pose.matrix().allFinite()) g.frame = pose;  // a bad answer keeps the last pose
    }
    const Vec3 before = g.pose.translation();
    g.stopped = false;
    g.pose = towards(g.pose, g.frame, g.local, max_move);
    if (pushes.cols() > 0) {
      Vec3 push = Vec3::Zero();
      for (int v : g.vertices) push += pushes.col(v);
      const double into = (g.pose.translation() - before).dot(push);
      // Stopped where it is: sliding along the contact, a gripper followed the stack's slope
      // down to where the layers thin out and squeezed them there.
      g.stopped = into < 0.0;
      if (g.stopped) g.pose.translation() = before;
    }
    g.lag = farthestMove(g.pose, g.frame, g.local);
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
