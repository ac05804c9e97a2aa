/// @file spatial_hash.h
/// A uniform hash grid over axis-aligned boxes. Items are stored in every cell their box
/// overlaps; a query visits only the cells its box overlaps, so with cells about the size of
/// an item a query costs O(1) on average and N queries cost O(N).
#pragma once

#include <algorithm>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include <Eigen/Geometry>

namespace cloth_sim {

class SpatialHash {
 public:
  /// @p cell_size in m, > 0.
  explicit SpatialHash(double cell_size = 1.0);

  /// Stores item @p id (>= 0, each id once) in every cell @p box overlaps.
  void insert(int id, const Eigen::AlignedBox3d& box);
  /// Calls visit(id) once for every stored item whose cells overlap @p box (a superset of the
  /// items whose boxes overlap it), in the order of the first cell where each is met. Const:
  /// any number of threads may query at once.
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
  std::vector<Eigen::Vector3i> low_;  ///< per item, the lowest cell of its box
};

template <typename Visit>
void SpatialHash::query(const Eigen::AlignedBox3d& box, Visit&& visit) const {
  const Eigen::Vector3i lo = cellOf(box.min()), hi = cellOf(box.max());
  for (int x = lo.x(); x <= hi.x(); ++x)
    for (int y = lo.y(); y <= hi.y(); ++y)
      for (int z = lo.z(); z <= hi.z(); ++z) {
        const auto it = cells_.find(key(x, y, z));
        if (it == cells_.end()) continue;
        for (int id : it->second) {
          // An item's cells form a box: the loops above meet it first in the cell whose
          // coordinates are the larger of its lowest cell's and the query's.
          const Eigen::Vector3i& low = low_[id];
          if (x != std::max(low.x(), lo.x()) || y != std::max(low.y(), lo.y()) ||
              z != std::max(low.z(), lo.z())) {
            continue;
          }
          visit(id);
        }
      }
}

}  // namespace cloth_sim
