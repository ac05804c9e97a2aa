/// @file free_particles.h
/// Which particles are unknowns of the implicit solve: all but the hard-pinned ones.
#pragma once

#include <vector>

#include "cloth_sim/core/model/pins.h"

namespace cloth_sim {

/// Maps particles to the reduced set of free unknowns (hard-pinned particles are removed,
/// their positions become known boundary values).
struct FreeParticleMap {
  std::vector<int> reduced_index;   ///< particle -> free index, or -1 when hard-pinned
  std::vector<int> free_particles;  ///< free index -> particle

  static FreeParticleMap fromPins(int particle_count, const PinSet& pins);
  int freeCount() const { return static_cast<int>(free_particles.size()); }
  bool isFree(int particle) const { return reduced_index[particle] >= 0; }
};

}  // namespace cloth_sim
