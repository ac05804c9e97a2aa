#include "cloth_sim/node/step_monitor.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

namespace cloth_sim::node {

StepMonitor::StepMonitor(double budget, int max_rollbacks)
    : budget_(budget), max_rollbacks_(max_rollbacks) {
  if (!(budget > 0.0)) throw std::invalid_argument("step budget must be > 0 s");
  if (max_rollbacks < 1) throw std::invalid_argument("max_rollbacks must be >= 1");
  window_.budget = budget_;
}

bool StepMonitor::record(bool rolled_back, double seconds, bool cut) {
  ++window_.steps;
  if (cut) ++window_.cut;
  window_time_sum_ += seconds;
  window_.max_time = std::max(window_.max_time, seconds);
  if (seconds > budget_) {
    ++window_.overruns;
    ++total_overruns_;
  }
  if (!rolled_back) {
    consecutive_failures_ = 0;
    return false;
  }
  ++window_.rollbacks;
  ++total_rollbacks_;
  if (static_cast<int>(++consecutive_failures_) < max_rollbacks_) return false;
  consecutive_failures_ = 0;
  ++divergence_resets_;
  ++window_.resets;
  return true;
}

void StepMonitor::holdInsteadOfReset() {
  if (divergence_resets_ > 0) --divergence_resets_;
  if (window_.resets > 0) --window_.resets;
}

StepWindow StepMonitor::takeWindow() {
  StepWindow w = window_;
  w.mean_time = w.steps > 0 ? window_time_sum_ / w.steps : 0.0;
  window_ = StepWindow();
  window_.budget = budget_;
  window_time_sum_ = 0.0;
  return w;
}

HealthReport assess(const StepWindow& w, double overrun_tolerance) {
  char buf[256];
  if (w.resets > 0) {
    std::snprintf(buf, sizeof buf,
                  "diverged: reset %d time(s) after repeated rolled-back steps (%d of %d steps "
                  "rolled back)",
                  w.resets, w.rollbacks, w.steps);
    return {Health::kError, buf};
  }
  if (w.steps == 0) return {Health::kWarn, "no step since the last report (stalled?)"};
  if (w.rollbacks > 0) {
    std::snprintf(buf, sizeof buf, "%d of %d steps diverged and were rolled back", w.rollbacks,
                  w.steps);
    return {Health::kWarn, buf};
  }
  if (w.overruns > overrun_tolerance * w.steps) {
    std::snprintf(buf, sizeof buf,
                  "slower than real time: %d of %d steps over the %.2f ms budget (mean %.2f ms)",
                  w.overruns, w.steps, 1e3 * w.budget, 1e3 * w.mean_time);
    return {Health::kWarn, buf};
  }
  std::snprintf(buf, sizeof buf, "%d steps, mean %.2f ms of the %.2f ms budget", w.steps,
                1e3 * w.mean_time, 1e3 * w.budget);
  return {Health::kOk, buf};
}

}  // namespace cloth_sim::node
