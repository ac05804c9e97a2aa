// Distances between two states of the same cloth and its springs' strain: how the accuracy
// benchmark and its peers (cloth_sim_bench peers) measure a run against the true motion.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>

#include "cloth_sim/core/model/model.h"

namespace cloth_sim::bench {

/// RMS over the particles of |a_i - b_i| (m).
inline double rms(const Points& a, const Points& b) {
  return std::sqrt((a - b).colwise().squaredNorm().mean());
}
/// max over the particles of |a_i - b_i| (m).
inline double maxDistance(const Points& a, const Points& b) {
  return (a - b).colwise().norm().maxCoeff();
}
/// |centre of mass of a - that of b| (m), particle masses @p mass.
inline double centerOfMassDistance(const Points& a, const Points& b, const Eigen::VectorXd& mass) {
  return ((a - b) * mass).norm() / mass.sum();
}
/// Mean and max over @p springs of |l - r| / r at @p x.
inline std::pair<double, double> springStrain(const Springs& springs, const Points& x) {
  double sum = 0.0, worst = 0.0;
  for (std::size_t k = 0; k < springs.size(); ++k) {
    const double length = (x.col(springs.first[k]) - x.col(springs.second[k])).norm();
    const double e = std::abs(length - springs.rest_length[k]) / springs.rest_length[k];
    sum += e;
    worst = std::max(worst, e);
  }
  return {springs.size() > 0 ? sum / static_cast<double>(springs.size()) : 0.0, worst};
}

}  // namespace cloth_sim::bench
