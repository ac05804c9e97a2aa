#include "cloth_sim/node/sim_clock.h"

#include <cstdint>
#include <cstdio>
#include <cstring>

namespace cloth_sim::node {
namespace {

void mix(std::uint64_t& hash, const void* data, std::size_t bytes) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t k = 0; k < bytes; ++k) {
    hash ^= p[k];
    hash *= 1099511628211ull;  // FNV-1a prime
  }
}

}  // namespace

std::string stateDigest(const State& state) {
  std::uint64_t hash = 14695981039346656037ull;  // FNV-1a offset basis
  mix(hash, state.positions.data(), sizeof(double) * state.positions.size());
  mix(hash, state.velocities.data(), sizeof(double) * state.velocities.size());
  mix(hash, &state.time, sizeof state.time);
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

}  // namespace cloth_sim::node
