#include "cloth_sim/core/simulation/frame_inputs.h"

#include <utility>

namespace cloth_sim {
namespace {

/// Where a target set at @p target stands at the end of the coming frame, having stood at
/// @p from at the end of the last one: @p target, or @p limit m of the way there.
Vec3 towards(const Vec3& from, const Vec3& target, double limit) {
  const Vec3 way = target - from;
  const double distance = way.norm();
  return distance <= limit ? target : Vec3(from + way * (limit / distance));
}

}  // namespace

void FrameInputs::startPinsAt(const PinSet& pins, const Points& positions) {
  frame_targets_.clear();
  for (const Pin& pin : pins.pins())
    frame_targets_.emplace_back(pin.id, Vec3(positions.col(pin.vertex)));
}

void FrameInputs::moveSphere(Colliders& colliders, int id, const Vec3& center,
                             const Vec3& velocity) {
  const SphereCollider* s = colliders.findSphere(id);
  const Vec3 from = s != nullptr ? s->center : center;
  colliders.moveSphere(id, center, velocity);         // validates; throws for an unknown id
  if (colliders.findSphere(id)->isDynamic()) return;  // a ball is placed at once
  // A kinematic sphere goes there across the next frame's substeps, sweeping the cloth.
  colliders.moveSphere(id, from, velocity);
  for (SphereJump& jump : sphere_jumps_) {
    if (jump.id == id) {
      jump.displacement = center - from;
      return;
    }
  }
  sphere_jumps_.push_back({id, center - from});
}

void FrameInputs::beginFrame(const PinSet& pins, double max_pin_move, double frame_time,
                             Colliders& colliders) {
  paths_.clear();
  max_pin_move_ = max_pin_move;
  placed_substeps_ = 0;
  for (const auto& [id, from] : frame_targets_) {
    const Pin* pin = pins.find(id);
    if (pin != nullptr && pin->target != from) {
      paths_.push_back({id, from, towards(from, pin->target, max_pin_move)});
    }
  }
  pins_at_ = paths_.empty() ? PinSet() : pins;
  applySphereJumps(+1.0, frame_time, colliders);
  frame_end_.clear();
  for (const Pin& pin : pins.pins()) frame_end_.emplace_back(pin.id, pin.target);
  for (const PinPath& path : paths_) {
    for (auto& [id, target] : frame_end_) {
      if (id == path.id) target = path.to;
    }
  }
}

const PinSet& FrameInputs::pinsAt(int k, int n, double time, GraspSet& grasps, PinSet& pins,
                                  const Points& pushes) {
  const bool moved = !paths_.empty();
  if (moved && pushes.cols() > 0) stopAtContacts(placed_substeps_, n, pushes);
  if (moved) {
    const double s = static_cast<double>(k) / n;
    for (const PinPath& path : paths_)
      pins_at_.moveTarget(path.id, path.from + s * (path.to - path.from));
  }
  if (!grasps.empty()) {
    const double max_move = max_pin_move_ * (k - placed_substeps_) / n;
    grasps.place(time, max_move, pins, moved ? &pins_at_ : nullptr, pushes);
  }
  placed_substeps_ = k;
  return moved ? pins_at_ : pins;
}

void FrameInputs::stopAtContacts(int done, int n, const Points& pushes) {
  for (PinPath& path : paths_) {
    const Pin* pin = pins_at_.find(path.id);
    if (pin == nullptr || !pin->isHard()) continue;
    const Vec3 push = pushes.col(pin->vertex);
    const Vec3 at = path.from + (static_cast<double>(done) / n) * (path.to - path.from);
    const double into = (path.to - at).dot(push);
    if (!(into < 0.0)) continue;
    // The rest of the way without its part into the contact, still reached at substep n: the
    // path from' -> to' that pinsAt's k / n interpolation puts at `at` after `done` substeps.
    const Vec3 to = path.to - (into / push.squaredNorm()) * push;
    const Vec3 way = (to - at) * (static_cast<double>(n) / (n - done));
    path.from = to - way;
    path.to = to;
    for (auto& [id, target] : frame_end_) {
      if (id == path.id) target = to;
    }
  }
}

void FrameInputs::endFrame(bool kept, const PinSet& pins, const GraspSet& grasps, double frame_time,
                           Colliders& colliders) {
  if (kept) {
    applySphereJumps(-1.0, frame_time, colliders);
  } else {
    // The user's sphere moves of a rolled-back frame stand: those spheres go where they were sent.
    for (const SphereJump& jump : sphere_jumps_) {
      if (const SphereCollider* s = colliders.findSphere(jump.id)) {
        colliders.moveSphere(jump.id, s->center + jump.displacement, s->velocity);
      }
    }
  }
  sphere_jumps_.clear();
  // A grasp's pins follow its frame (GraspSet::place, at the speed limit), not a user's move.
  for (auto& [id, target] : frame_end_) {
    if (grasps.graspOf(id) != nullptr) target = pins.find(id)->target;
  }
  frame_targets_ = std::move(frame_end_);
  frame_end_.clear();
  paths_.clear();
}

void FrameInputs::applySphereJumps(double sign, double frame_time, Colliders& colliders) const {
  for (const SphereJump& jump : sphere_jumps_) {
    const SphereCollider* s = colliders.findSphere(jump.id);
    if (s == nullptr) continue;
    colliders.moveSphere(jump.id, s->center, s->velocity + sign * jump.displacement / frame_time);
  }
}

}  // namespace cloth_sim
