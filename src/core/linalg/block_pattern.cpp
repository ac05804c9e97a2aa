#include "cloth_sim/core/linalg/block_pattern.h"

#include <algorithm>
#include <stdexcept>

namespace cloth_sim {

BlockPattern::BlockPattern(int nodes, int block, const std::vector<std::pair<int, int>>& pairs)
    : block_(block) {
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<std::size_t>(nodes + 2 * pairs.size()) * block * block);
  auto add_block = [&](int i, int j) {
    for (int a = 0; a < block; ++a)
      for (int b = 0; b < block; ++b) entries.emplace_back(i * block + a, j * block + b, 0.0);
  };
  for (int i = 0; i < nodes; ++i) add_block(i, i);
  for (const auto& [i, j] : pairs) {
    add_block(i, j);
    add_block(j, i);
  }
  matrix_.resize(nodes * block, nodes * block);
  matrix_.setFromTriplets(entries.begin(), entries.end());
  matrix_.makeCompressed();
}

int BlockPattern::columnStart(int i, int j, int b) const {
  const int col = j * block_ + b;
  const int row = i * block_;
  const int* begin = matrix_.innerIndexPtr() + matrix_.outerIndexPtr()[col];
  const int* end = matrix_.innerIndexPtr() + matrix_.outerIndexPtr()[col + 1];
  const int* it = std::lower_bound(begin, end, row);
  if (it == end || *it != row) throw std::logic_error("BlockPattern: block not in pattern");
  return static_cast<int>(it - matrix_.innerIndexPtr());
}

}  // namespace cloth_sim
