/// @file spatial_hash.h
/// A uniform hash grid over axis-aligned boxes. Items are stored in every cell their box
/// overlaps; a query visits only the cells its box overlaps, so with cells about the size of
/// an item a query costs O(1) on average and N queries cost O(N).
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include <Eigen/Geometry>

namespace cloth_sim {

class SpatialHash {
 public:
  /// @p cell_size in m, > 0.
  explicit SpatialHash(double cell_size = 1.0);

  /// Stores item @p id (>= 0) in every cell @p box overlaps.
  void insert(int id, const Eigen::AlignedBox3d& box);
  /// Calls visit(id) once for every stored item whose cells overlap @p box (a superset of the
  /// items whose boxes overlap it). Not thread-safe (it keeps a visit stamp per item).
  template <typename Visit>
  void query(const Eigen::AlignedBox3d& box, Visit&& visit) const;


 private:
  using Key = std::uint64_t;
  Eigen::Vector3i cellOf(const Eigen::Vector3d& p) const {
    return (p / cell_size_).array().floor().cast<int>();
  }
  static Key key(int x, int y, int z);

  double cell_size_;
  std::unordered_map<Key, std::vector<int>> cells_;
  mutable std::vector<unsigned> stamp_;
  mutable unsigned epoch_ = 0;
};

template <typename Visit>
void SpatialHash::query(const Eigen::AlignedBox3d& box, Visit&& visit) const {
  if (++epoch_ == 0) {  // wrapped: forget every stamp
    std::fill(stamp_.begin(), stamp_.end(), 0u);
    epoch_ = 1;
  }
  const Eigen::Vector3i lo = cellOf(box.min()), hi = cellOf(box.max());
  for (int x = lo.x(); x <= hi.x(); ++x)
    for (int y = lo.y(); y <= hi.y(); ++y)
      for (int z = lo.z(); z <= hi.z(); ++z) {
        const auto it = cells_.find(key(x, y, z));
        if (it == cells_.end()) continue;
        for (int id : it->second) {
          if (stamp_[id] == epoch_) continue;
          stamp_[id] = epoch_;
          visit(id);
        }
      }
}

}  // namespace cloth_sim
