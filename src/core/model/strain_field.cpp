#include "cloth_sim/core/model/strain_field.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace cloth_sim {

Eigen::VectorXd vertexStrain(const Model& model, const Points& positions) {
  const int n = model.particleCount();
  if (positions.cols() != n) {
    throw std::invalid_argument("vertexStrain: " + std::to_string(positions.cols()) +
                                " positions for " + std::to_string(n) + " particles");
  }
  const bool in_plane_only = model.familySize(SpringFamily::kStructural) > 0 ||
                             model.familySize(SpringFamily::kShear) > 0;
  const Springs& springs = model.springs;
  Eigen::VectorXd strain = Eigen::VectorXd::Zero(n);
  for (std::size_t s = 0; s < springs.size(); ++s) {
    if (in_plane_only && springs.family[s] == SpringFamily::kBending) continue;
    const int i = springs.first[s], j = springs.second[s];
    const double length = (positions.col(i) - positions.col(j)).norm();
    const double e = (length - springs.rest_length[s]) / springs.rest_length[s];
    if (!std::isfinite(e)) continue;
    if (std::abs(e) > std::abs(strain[i])) strain[i] = e;
    if (std::abs(e) > std::abs(strain[j])) strain[j] = e;
  }
  return strain;
}

}  // namespace cloth_sim
