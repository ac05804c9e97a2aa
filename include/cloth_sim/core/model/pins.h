/// @file pins.h
/// Pins attach a particle to a movable target point.
#pragma once

#include <vector>

#include "cloth_sim/core/linalg/types.h"

namespace cloth_sim {

/// A particle attached to a target point.
///
/// A hard pin (stiffness 0) removes the particle from the unknowns: it sits exactly on its target.
/// A soft pin (stiffness > 0) is Liu et al.'s zero-rest-length spring to the target, energy
/// 1/2 stiffness |x - target|^2. Either way moving the target changes only a right-hand side,
/// never the factored matrix.
struct Pin {
  int id = -1;            ///< stable handle, unique within a PinSet
  int vertex = -1;        ///< pinned particle index
  Vec3 target = Vec3::Zero();  ///< m, world frame
  double stiffness = 0.0;      ///< N/m; 0 = hard pin

  bool isHard() const { return stiffness == 0.0; }
};

/// The pins of a simulation, with stable ids. At most one pin per particle.
class PinSet {
 public:
  /// Adds a pin and returns its id. Throws std::invalid_argument if the vertex is out of
  /// [0, particle_count), already pinned, the target is not finite or the stiffness is < 0.
  int add(int vertex, const Vec3& target, double stiffness, int particle_count);
  /// Removes pin @p id; throws std::invalid_argument if there is none.
  void remove(int id);
  /// Moves the target of pin @p id; throws std::invalid_argument if unknown or not finite.
  void moveTarget(int id, const Vec3& target);
  /// The pin with @p id, or nullptr.
  const Pin* find(int id) const;
  /// The pin on @p vertex, or nullptr.
  const Pin* findByVertex(int vertex) const;

  const std::vector<Pin>& pins() const { return pins_; }
  std::size_t size() const { return pins_.size(); }
  bool empty() const { return pins_.empty(); }

 private:
  std::vector<Pin> pins_;
  int next_id_ = 0;
};

}  // namespace cloth_sim
