#include "cloth_sim/core/collision/proximity_projection.h"

#include "cloth_sim/core/collision/contact_projection.h"

namespace cloth_sim {

int projectProximity(const std::vector<PairContact>& contacts, const std::vector<int>& active,
                     const CollisionStep& step, const GroundPlane& ground, double mu, int sweeps,
                     Points& end) {
  int corrections = 0;
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    for (int index : active) {
      const PairContact& c = contacts[index];
      const double gap = proximityGap(c, end);
      if (gap >= 0.0) continue;
      std::array<double, 4> inv{};
      double denom = 0.0;
      for (int k = 0; k < 4; ++k) {
        const int v = c.pair.v[k];
        inv[k] = step.movable[v] ? 1.0 / step.mass[v] : 0.0;
        // A particle on the ground that the push would move down is held by the ground: the
        // other side takes the whole push (else the clamp below undid it sweep after sweep and
        // pressed a layer lying on a grounded one into its plane).
        if (ground.enabled && end(2, v) <= ground.height && c.weight[k] * c.normal.z() < 0.0) {
          inv[k] = 0.0;
        }
        denom += c.weight[k] * c.weight[k] * inv[k];
      }
      if (!(denom > 0.0)) continue;  // all four pinned (or on a weight of 0)
      // x_k += inv_k w_k lambda n moves the gap by lambda denom: lambda closes it exactly, and
      // sum_k m_k dx_k = lambda n sum_k w_k = 0 (the weights sum to zero).
      const double lambda = -gap / denom;
      for (int k = 0; k < 4; ++k) end.col(c.pair.v[k]) += (inv[k] * c.weight[k] * lambda) * c.normal;
      // Friction on the closest points' relative slide over the substep.
      Vec3 slide = Vec3::Zero();
      for (int k = 0; k < 4; ++k) {
        const int v = c.pair.v[k];
        slide += c.weight[k] * (end.col(v) - step.start.col(v));
      }
      const Vec3 cut = slide - applyFriction(slide, c.normal, -gap, mu);
      if (!cut.isZero(0.0)) {
        for (int k = 0; k < 4; ++k) end.col(c.pair.v[k]) -= (inv[k] * c.weight[k] / denom) * cut;
      }
      ++corrections;
    }
    if (ground.enabled) {
      for (int index : active) {
        for (int v : contacts[index].pair.v) {
          if (step.movable[v] && end(2, v) < ground.height) end(2, v) = ground.height;
        }
      }
    }
  }
  return corrections;
}

}  // namespace cloth_sim
