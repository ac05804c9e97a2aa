#include "cloth_sim/core/collision/spatial_hash.h"

#include <cmath>
#include <stdexcept>

namespace cloth_sim {

SpatialHash::SpatialHash(double cell_size) : cell_size_(cell_size) {
  if (!(std::isfinite(cell_size) && cell_size > 0.0)) {
    throw std::invalid_argument("spatial hash cell size must be finite and > 0");
  }
}

SpatialHash::Key SpatialHash::key(int x, int y, int z) {
  // 21 bits per axis (two's complement folded): distinct keys within +-2^20 cells.
  const auto fold = [](int v) { return static_cast<Key>(static_cast<std::uint32_t>(v) & 0x1FFFFFu); };
  return fold(x) | (fold(y) << 21) | (fold(z) << 42);
}

void SpatialHash::insert(int id, const Eigen::AlignedBox3d& box) {
  const Eigen::Vector3i lo = cellOf(box.min()), hi = cellOf(box.max());
  if (id >= static_cast<int>(low_.size())) low_.resize(id + 1, Eigen::Vector3i::Zero());
  low_[id] = lo;
  for (int x = lo.x(); x <= hi.x(); ++x)
    for (int y = lo.y(); y <= hi.y(); ++y)
      for (int z = lo.z(); z <= hi.z(); ++z) cells_[key(x, y, z)].push_back(id);
}

}  // namespace cloth_sim
