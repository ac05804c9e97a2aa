#include "cloth_sim/core/collision/additive_ccd.h"

#include <algorithm>

namespace cloth_sim {

ClosestPoints closestPoints(PairKind kind, const PairPoints& x) {
  return kind == PairKind::kVertexTriangle ? pointTriangle(x[0], x[1], x[2], x[3])
                                           : segmentSegment(x[0], x[1], x[2], x[3]);
}

CcdResult additiveCcd(PairKind kind, const PairPoints& x0, const PairPoints& motion,
                      double min_distance, int max_iterations) {
  CcdResult result;
  const Vec3 mean = 0.25 * (motion[0] + motion[1] + motion[2] + motion[3]);
  PairPoints d;
  for (int k = 0; k < 4; ++k) d[k] = motion[k] - mean;
  const double l =
      kind == PairKind::kVertexTriangle
          ? d[0].norm() + std::max({d[1].norm(), d[2].norm(), d[3].norm()})
          : std::max(d[0].norm(), d[1].norm()) + std::max(d[2].norm(), d[3].norm());
  const double gap0 = closestPoints(kind, x0).distance - min_distance;
  if (!(gap0 > 0.0)) {
    result.safe_time = 0.0;
    return result;
  }
  if (gap0 > l) return result;  // cannot close the gap within the motion (also l = 0)
  double time = 0.0, gap = gap0;
  PairPoints x;
  while (true) {
    const double advance = 0.9 * gap / l;
    if (time + advance >= 1.0) return result;  // safe to the end
    if (result.iterations >= max_iterations) break;
    time += advance;
    for (int k = 0; k < 4; ++k) x[k] = x0[k] + time * d[k];
    ++result.iterations;
    gap = closestPoints(kind, x).distance - min_distance;
    if (gap < 0.01 * gap0) break;  // about to touch: stop here
  }
  result.safe_time = time;
  return result;
}

}  // namespace cloth_sim
