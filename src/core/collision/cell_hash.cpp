#include "cloth_sim/core/collision/cell_hash.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace cloth_sim {

void CellHash::build(const Points& keys, double cell_size) {
  if (!(std::isfinite(cell_size) && cell_size > 0.0)) {
    throw std::invalid_argument("cell hash: cell size " + std::to_string(cell_size) +
                                " m must be finite and > 0");
  }
  // Cells are ints: a key beyond 2^30 cells would overflow the cast.
  if (!keys.allFinite() || (keys.cols() > 0 && keys.cwiseAbs().maxCoeff() / cell_size > 1e9)) {
    throw std::invalid_argument("cell hash: keys must be finite and within 1e9 cells of 0");
  }
  cell_size_ = cell_size;
  const std::size_t n = static_cast<std::size_t>(keys.cols());
  std::size_t table = 1;
  while (table < 2 * n) table <<= 1;  // load <= 1/2
  mask_ = table - 1;
  start_.assign(table + 1, 0);
  item_cell_.resize(n);
  item_slot_.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    item_cell_[k] = cellOf(keys.col(static_cast<Eigen::Index>(k)));
    item_slot_[k] = slot(item_cell_[k]);
    ++start_[item_slot_[k] + 1];
  }
  for (std::size_t s = 0; s < table; ++s) start_[s + 1] += start_[s];
  ids_.resize(n);
  cells_.resize(n);
  // Fill from the back of each slot's range, so start_[s] ends at the range's first entry.
  for (std::size_t k = n; k-- > 0;) {
    const int e = --start_[item_slot_[k] + 1];
    ids_[e] = static_cast<int>(k);
    cells_[e] = item_cell_[k];
  }
  // start_[s + 1] now holds the first entry of slot s: shift back by one slot.
  for (std::size_t s = 0; s < table; ++s) start_[s] = start_[s + 1];
  start_[table] = static_cast<int>(n);
}

}  // namespace cloth_sim
