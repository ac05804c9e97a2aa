#include "cloth_sim/core/model/free_particles.h"

namespace cloth_sim {

FreeParticleMap FreeParticleMap::fromPins(int particle_count, const PinSet& pins) {
  FreeParticleMap map;
  map.reduced_index.assign(particle_count, 0);
  for (const Pin& p : pins.pins()) {
    if (p.isHard()) map.reduced_index[p.vertex] = -1;
  }
  map.free_particles.reserve(particle_count);
  for (int i = 0; i < particle_count; ++i) {
    if (map.reduced_index[i] < 0) continue;
    map.reduced_index[i] = static_cast<int>(map.free_particles.size());
    map.free_particles.push_back(i);
  }
  return map;
}

}  // namespace cloth_sim
