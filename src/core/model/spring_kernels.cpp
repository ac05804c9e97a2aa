#include "cloth_sim/core/model/spring_kernels.h"

#include <algorithm>
#include <cmath>

namespace cloth_sim {

Vec3 safeDirection(const Vec3& d) {
  const double len = d.norm();
  if (len > 1e-300 && std::isfinite(len)) return d / len;
  return Vec3::UnitX();
}

double springEnergy(const Springs& springs, const Points& x) {
  double energy = 0.0;
  const std::size_t m = springs.size();
  for (std::size_t s = 0; s < m; ++s) {
    const double stretch =
        (x.col(springs.first[s]) - x.col(springs.second[s])).norm() - springs.rest_length[s];
    energy += 0.5 * springs.stiffness[s] * stretch * stretch;
  }
  return energy;
}

void addSpringForces(const Springs& springs, const Points& x, Points& forces) {
  const std::size_t m = springs.size();
  for (std::size_t s = 0; s < m; ++s) {
    const int i = springs.first[s], j = springs.second[s];
    const Vec3 d = x.col(i) - x.col(j);
    const double len = d.norm();
    // f_i = -k (l - r) d/l; written as k (r/l - 1) d to stay finite for l -> 0 only via safeDirection.
    const Vec3 f = -springs.stiffness[s] * (len - springs.rest_length[s]) * safeDirection(d);
    forces.col(i) += f;
    forces.col(j) -= f;
  }
}

double maxStrain(const Springs& springs, const Points& x) {
  double worst = 0.0;
  const std::size_t m = springs.size();
  for (std::size_t s = 0; s < m; ++s) {
    const double len = (x.col(springs.first[s]) - x.col(springs.second[s])).norm();
    const double strain = std::abs(len - springs.rest_length[s]) / springs.rest_length[s];
    // Propagate NaN: std::max would silently drop it.
    if (!(strain <= worst)) worst = strain;
  }
  return worst;
}

Eigen::Matrix3d springHessianBlock(const Vec3& d, double rest_length, double stiffness,
                                   bool clamp_psd) {
  const double len = d.norm();
  const Vec3 u = safeDirection(d);
  const Eigen::Matrix3d uu = u * u.transpose();
  // A collapsed spring (len -> 0) has an unbounded transverse term: always clamp it.
  double transverse = (len > 1e-12 * rest_length) ? 1.0 - rest_length / len : 0.0;
  if (clamp_psd) transverse = std::max(0.0, transverse);
  return stiffness * (uu + transverse * (Eigen::Matrix3d::Identity() - uu));
}

}  // namespace cloth_sim
