#include "cloth_sim/core/simulation/step_controller.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace cloth_sim {

StepController::StepController(double tolerance, int order, int min_substeps, int max_substeps)
    : tolerance_(tolerance), order_(order), min_(min_substeps), max_(max_substeps) {
  if (!(std::isfinite(tolerance) && tolerance > 0.0)) {
    throw std::invalid_argument("error tolerance " + std::to_string(tolerance) +
                                " m must be finite and > 0");
  }
  if (order < 1) throw std::invalid_argument("integrator order must be >= 1");
  if (min_substeps < 1 || max_substeps < min_substeps) {
    throw std::invalid_argument("substeps [" + std::to_string(min_substeps) + ", " +
                                std::to_string(max_substeps) + "] must satisfy 1 <= min <= max");
  }
}

namespace {

/// The rung after @p rung: 1, 2, 3, 4, 6, 8, 12, 16, 24, ... (a power of two p >= 2 is followed
/// by 3p/2, 3p/2 by 2p): steps of 1.33-1.5x, each count a factor that can be kept.
int nextRung(int rung) {
  if (rung < 2) return 2;
  const bool power_of_two = (rung & (rung - 1)) == 0;
  return power_of_two ? rung + rung / 2 : rung / 3 * 4;
}

}  // namespace

int StepController::rungAtLeast(int n) {
  int rung = 1;
  while (rung < n) rung = nextRung(rung);
  return rung;
}

int StepController::rungBelow(int n) {
  int below = 1;
  for (int rung = 1; rung < n; rung = nextRung(rung)) below = rung;
  return below;
}

void StepController::setMaxSubsteps(int max_substeps) { max_ = std::max(min_, max_substeps); }

StepController::Decision StepController::next(int substeps, double error, double iterations) {
  Decision d;
  const int n = std::clamp(substeps, min_, max_);
  const double ratio = std::isfinite(error) ? std::max(0.0, error) / tolerance_ : 1e300;
  // Slow iterations: one rung more makes the frame cheaper (the class comment).
  const int faster = iterations > kSlowIterations ? std::min(rungAtLeast(n + 1), max_) : n;
  if (ratio > 1.0) {
    calm_frames_ = 0;
    const double wanted = n * std::pow(ratio / kSafety, 1.0 / order_);
    const double grown = std::min(wanted, double(n) * kMaxGrowth);
    const int rung = rungAtLeast(static_cast<int>(std::ceil(std::min(grown, 1e9))));
    d.substeps = std::max(std::min(rung, max_), faster);
    d.capped = wanted > max_;
    return d;
  }
  d.substeps = faster;
  if (faster > n) {
    calm_frames_ = 0;
    return d;
  }
  const int down = std::max(min_, rungBelow(n));
  const double scale = double(n) / down;
  const double excess = std::max(0.0, iterations - kLeastIterations);
  const bool iterations_allow =
      kLeastIterations + excess * std::pow(scale, kIterationExponent) <= kSlowIterations;
  if (down < n && ratio * std::pow(scale, order_) < kDownShare && iterations_allow) {
    if (++calm_frames_ >= kPatience) {
      calm_frames_ = 0;
      d.substeps = down;
    }
  } else {
    calm_frames_ = 0;
  }
  return d;
}

}  // namespace cloth_sim
