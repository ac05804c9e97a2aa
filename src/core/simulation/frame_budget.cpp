#include "cloth_sim/core/simulation/frame_budget.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace cloth_sim {
namespace {
/// Weight of the newest frame in the average: about the last five frames count.
constexpr double kAverageWeight = 0.2;
/// Frames after a change before the average may take the substeps down again.
constexpr int kSettle = 3;
}  // namespace

FrameBudget::FrameBudget(double budget_s, int min_substeps, int max_substeps)
    : budget_(budget_s), min_substeps_(min_substeps), max_substeps_(max_substeps) {
  if (!(std::isfinite(budget_s) && budget_s > 0.0)) {
    throw std::invalid_argument("frame budget " + std::to_string(budget_s) +
                                " s must be finite and > 0");
  }
  if (min_substeps < 1 || max_substeps < min_substeps) {
    throw std::invalid_argument("frame budget substeps [" + std::to_string(min_substeps) + ", " +
                                std::to_string(max_substeps) + "] must satisfy 1 <= min <= max");
  }
}

int FrameBudget::next(int substeps, double frame_wall_s) {
  if (!(std::isfinite(frame_wall_s) && frame_wall_s > 0.0) || substeps < 1) return substeps;
  if (skip_next_) {
    skip_next_ = false;
    return substeps;
  }
  const double per_substep = frame_wall_s / substeps;
  cost_ = cost_ > 0.0 ? (1.0 - kAverageWeight) * cost_ + kAverageWeight * per_substep : per_substep;
  ++frames_since_change_;
  const double fit_real = kHeadroom * budget_ / cost_;
  const int fit = static_cast<int>(
      std::clamp(std::floor(fit_real), double(min_substeps_), double(max_substeps_)));
  int chosen = substeps;
  if (cost_ * substeps > budget_ && fit < substeps && frames_since_change_ >= kSettle) {
    chosen = fit;
  } else if (fit > substeps && frames_since_change_ >= kPatience) {
    chosen = std::min(fit, substeps + std::max(1, substeps / 4));
  }
  chosen = std::clamp(chosen, min_substeps_, max_substeps_);
  if (chosen != substeps) {
    frames_since_change_ = 0;
    skip_next_ = true;
  }
  return chosen;
}

}  // namespace cloth_sim
