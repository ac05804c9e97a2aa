#include "cloth_sim/core/collision/proximity_projection.h"

#include <algorithm>
#include <vector>

#include "cloth_sim/core/collision/contact_projection.h"

namespace cloth_sim {

bool pushApart(const std::array<int, 4>& v, const std::array<double, 4>& weight,
               const Vec3& normal, double gap, const CollisionStep& step,
               const GroundPlane& ground, double mu, Points& end, Points* carry) {
  std::array<double, 4> inv{};
  double denom = 0.0;
  for (int k = 0; k < 4; ++k) {
    inv[k] = step.movable[v[k]] ? 1.0 / step.mass[v[k]] : 0.0;
    // A particle on the ground that the push would move down is held by the ground: the other
    // side takes the whole push (else the clamp undid it sweep after sweep and pressed a layer
    // lying on a grounded one into its plane).
    if (ground.enabled && end(2, v[k]) <= ground.height && weight[k] * normal.z() < 0.0) {
      inv[k] = 0.0;
    }
    denom += weight[k] * weight[k] * inv[k];
  }
  if (!(denom > 0.0)) return false;  // all four pinned (or on a weight of 0)
  // x_k += inv_k w_k lambda n moves the gap by lambda denom: lambda closes it exactly, and
  // sum_k m_k dx_k = lambda n sum_k w_k = 0 (the weights sum to zero).
  const double lambda = -gap / denom;
  for (int k = 0; k < 4; ++k) end.col(v[k]) += (inv[k] * weight[k] * lambda) * normal;
  if (carry != nullptr) {
    // The approach over the substep as the velocities see it, stopped by at most the push.
    double approach = 0.0;
    for (int k = 0; k < 4; ++k) {
      approach -= weight[k] * normal.dot(carry->col(v[k]) - step.start.col(v[k]));
    }
    const double share = std::clamp(approach / -gap, 0.0, 1.0);
    if (share > 0.0) {
      for (int k = 0; k < 4; ++k) {
        carry->col(v[k]) += (share * inv[k] * weight[k] * lambda) * normal;
      }
    }
  }
  if (mu > 0.0) {  // friction on the closest points' relative slide over the substep
    Vec3 slide = Vec3::Zero();
    for (int k = 0; k < 4; ++k) slide += weight[k] * (end.col(v[k]) - step.start.col(v[k]));
    const Vec3 cut = slide - applyFriction(slide, normal, -gap, mu);
    if (!cut.isZero(0.0)) {
      for (int k = 0; k < 4; ++k) {
        const Vec3 dx = (inv[k] * weight[k] / denom) * cut;
        end.col(v[k]) -= dx;
        if (carry != nullptr) carry->col(v[k]) -= dx;
      }
    }
  }
  return true;
}

int projectProximity(const std::vector<PairContact>& contacts, const std::vector<int>& active,
                     const CollisionStep& step, const GroundPlane& ground, double mu, int sweeps,
                     Points& end, Points* carry) {
  int corrections = 0;
  // After the first sweep, a contact's gap changes only if one of its particles moved.
  std::vector<char> moved(end.cols(), 1), moving(end.cols(), 0);
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    int pushed = 0;
    for (int index : active) {
      const PairContact& c = contacts[index];
      const auto& v = c.pair.v;
      if (!(moved[v[0]] || moved[v[1]] || moved[v[2]] || moved[v[3]])) continue;
      const double gap = proximityGap(c, end);
      if (gap >= -1e-3 * c.contact_distance) continue;  // within 0.1 % of it: done
      ++pushed;
      if (pushApart(c.pair.v, c.weight, c.normal, gap, step, ground, mu, end, carry)) {
        ++corrections;
        for (int k = 0; k < 4; ++k) moving[v[k]] = 1;
      }
    }
    if (ground.enabled) {
      for (int index : active) {
        for (int v : contacts[index].pair.v) {
          if (!step.movable[v]) continue;
          if (end(2, v) < ground.height) {
            end(2, v) = ground.height;
            moving[v] = 1;
          }
          if (carry != nullptr && (*carry)(2, v) < ground.height) (*carry)(2, v) = ground.height;
        }
      }
    }
    if (pushed == 0) break;
    moved.swap(moving);
    std::fill(moving.begin(), moving.end(), 0);
  }
  return corrections;
}

}  // namespace cloth_sim
