/// @file cell_hash.h
/// A hash grid rebuilt from scratch every time it is used (per substep or per frame): each item
/// is one key point (a particle, or the min corner of a triangle's box) stored in the one cell
/// that contains it. Built by a counting sort into a flat array (no allocation once warm), so a
/// rebuild of N items costs O(N) and a query visits only the items of the cells it overlaps.
/// Self-contact (self_contact.h) and the intersection counter (triangle_intersection.h) share it.
///
/// Why not SpatialHash: that one stores boxes in an unordered_map of vectors, fine for a static
/// obstacle built once, but rebuilding it for 16k particles at every substep allocated and cost
/// more than the contact it served.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Geometry>

#include "cloth_sim/core/linalg/types.h"

namespace cloth_sim {

class CellHash {
 public:
  /// Stores column k of @p keys (m) as item k in cells of side @p cell_size (m, > 0, finite).
  /// Throws std::invalid_argument for a bad cell size or a non-finite key.
  void build(const Points& keys, double cell_size);

  /// Calls visit(id) once for every item whose key lies in a cell overlapping @p box: a superset
  /// of the items whose key is in @p box. An item whose key point is its box's min corner and
  /// whose box is at most one cell wide overlaps @p box only if its key is in
  /// [box.min - cell, box.max], so query that box to find every overlapping item.
  template <typename Visit>
  void query(const Eigen::AlignedBox3d& box, Visit&& visit) const;

  double cellSize() const { return cell_size_; }
  int size() const { return static_cast<int>(ids_.size()); }

 private:
  Eigen::Vector3i cellOf(const Vec3& p) const {
    return (p / cell_size_).array().floor().cast<int>();
  }
  std::size_t slot(const Eigen::Vector3i& c) const {
    // Teschner et al. 2003, "Optimized spatial hashing for collision detection of deformable
    // objects": the three large primes, table size a power of two.
    const auto x = static_cast<std::uint32_t>(c.x()) * 73856093u;
    const auto y = static_cast<std::uint32_t>(c.y()) * 19349663u;
    const auto z = static_cast<std::uint32_t>(c.z()) * 83492791u;
    return (x ^ y ^ z) & mask_;
  }

  double cell_size_ = 1.0;
  std::size_t mask_ = 0;
  std::vector<int> start_;              ///< slot -> first entry; size table + 1
  std::vector<int> ids_;                ///< entries sorted by slot
  std::vector<Eigen::Vector3i> cells_;  ///< the cell of each entry (rejects slot collisions)
  std::vector<Eigen::Vector3i> item_cell_;
  std::vector<std::size_t> item_slot_;
};

template <typename Visit>
void CellHash::query(const Eigen::AlignedBox3d& box, Visit&& visit) const {
  if (ids_.empty()) return;
  const Eigen::Vector3i lo = cellOf(box.min()), hi = cellOf(box.max());
  const Eigen::Vector3i span = hi - lo + Eigen::Vector3i::Ones();
  const double cells = static_cast<double>(span.x()) * span.y() * span.z();
  if (cells > static_cast<double>(ids_.size())) {  // a huge box: scan every item once
    for (std::size_t e = 0; e < ids_.size(); ++e) {
      const Eigen::Vector3i& c = cells_[e];
      if ((c.array() >= lo.array()).all() && (c.array() <= hi.array()).all()) visit(ids_[e]);
    }
    return;
  }
  for (int x = lo.x(); x <= hi.x(); ++x)
    for (int y = lo.y(); y <= hi.y(); ++y)
      for (int z = lo.z(); z <= hi.z(); ++z) {
        const Eigen::Vector3i c(x, y, z);
        const std::size_t s = slot(c);
        for (int e = start_[s]; e < start_[s + 1]; ++e) {
          if (cells_[e] == c) visit(ids_[e]);
        }
      }
}

}  // namespace cloth_sim
