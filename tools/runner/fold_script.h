// The fold scene's script for the runner: the scene's first pin carried over the cloth and let go.
#pragma once

#include "cloth_sim/core/simulation/simulation.h"

namespace cloth_sim::tools {

/// Moves pin @p sim.pins()[0] from its target along a half-sine arc (up to a third of the way
/// it travels) onto the vertex farthest from it at rest, raised by kLayersUnderCorner
/// self-contact thicknesses when self-collision is on, in @p duration s; removes the pin the
/// frame after.
class FoldScript {
 public:
  /// Cloth layers the carried corner is set down on (the lower layer and the flap beneath it).
  static constexpr double kLayersUnderCorner = 2.0;
  /// Throws std::invalid_argument when the scene has no pin.
  FoldScript(const Simulation& sim, double duration);
  /// Call before each Simulation::step().
  void beforeStep(Simulation& sim);

 private:
  int pin_ = -1;
  Vec3 from_ = Vec3::Zero(), to_ = Vec3::Zero();
  double duration_, lift_ = 0.0;
  int frame_ = 0;
  bool released_ = false;
};

}  // namespace cloth_sim::tools
