#include "cloth_sim/node/diagnostics_report.h"

#include <algorithm>
#include <cstdio>

namespace cloth_sim::node {
namespace {

/// @p value with 3 decimals ("%.3f").
std::string fixed3(double value) {
  char text[64];
  std::snprintf(text, sizeof text, "%.3f", value);
  return text;
}

}  // namespace

double RealTimeWindow::take(double wall_now) {
  const double wall = wall_now - start_;
  const double factor = wall > 0.0 ? sim_time_ / wall : 0.0;
  start_ = wall_now;
  sim_time_ = 0.0;
  return factor;
}

DiagnosticsReport diagnosticsReport(const DiagnosticsInput& in) {
  const HealthReport health = assess(in.window);
  DiagnosticsReport r{health.level, health.message, {}};
  const StepWindow& w = in.window;
  auto add = [&r](const char* key, std::string value) {
    r.values.emplace_back(key, std::move(value));
  };
  add("scene", in.scene);
  add("solver", in.solver);
  add("substeps per frame", std::to_string(in.substeps));
  add("frame budget (ms)", fixed3(1e3 * in.frame_budget));
  add("iterations per substep", std::to_string(in.iterations));
  char metres[64];
  std::snprintf(metres, sizeof metres, "%.3g", in.error_tolerance);
  add("error tolerance (m)", metres);
  std::snprintf(metres, sizeof metres, "%.3g", in.error_estimate);
  add("error estimate (m)", metres);
  std::snprintf(metres, sizeof metres, "%.3g", in.carried_iteration_error);
  add("iteration error carried (m)", metres);
  add("step budget (ms)", fixed3(1e3 * w.budget));
  add("mean step time (ms)", fixed3(1e3 * w.mean_time));
  add("max step time (ms)", fixed3(1e3 * w.max_time));
  add("steps", std::to_string(w.steps));
  add("overruns", std::to_string(w.overruns));
  add("rolled-back steps", std::to_string(w.rollbacks));
  add("real-time factor", fixed3(in.real_time_factor));
  add("total overruns", std::to_string(in.total_overruns));
  add("total rolled-back steps", std::to_string(in.total_rollbacks));
  add("consecutive rolled-back steps", std::to_string(in.consecutive_failures));
  add("divergence resets", std::to_string(in.divergence_resets));
  add("sim time (s)", fixed3(in.sim_time));
  add("pins", std::to_string(in.pins));
  add("spheres", std::to_string(in.spheres));
  add("grasps", std::to_string(in.grasps));
  add("paused", in.paused ? "yes" : "no");
  add("frame deadline (ms)", fixed3(1e3 * in.frame_deadline));
  add("frames cut at the deadline", std::to_string(w.cut));
  auto warn = [&r](const std::string& what) {  // as DiagnosticStatusWrapper::mergeSummary(WARN)
    r.message = r.level != Health::kOk && !r.message.empty() ? r.message + "; " + what : what;
    r.level = std::max(r.level, Health::kWarn);
  };
  if (in.tolerance_unreachable) {
    warn("the error tolerance needs more substeps than the maximum or the frame budget allow");
  }
  if (w.cut > 0) {
    char text[200];
    std::snprintf(text, sizeof text,
                  "%d of %d frames cut at the %.0f ms frame deadline: the settings ask for more "
                  "work than a frame can hold (fewer iterations or substeps)",
                  w.cut, w.steps, 1e3 * in.frame_deadline);
    warn(text);
  }
  if (!in.notice.empty()) {
    warn(in.notice);
    add("held input", in.notice);
  }
  if (!in.stale_grasp_frames.empty()) {
    std::string frames;
    for (const std::string& f : in.stale_grasp_frames) frames += (frames.empty() ? "" : ", ") + f;
    warn("grasp frame stopped updating, held at its last pose: " + frames);
    add("stale grasp frames", frames);
  }
  const auto listed = [](const std::vector<std::pair<int, double>>& lags) {
    std::string grasps;
    for (const auto& [id, lag] : lags) {
      grasps += (grasps.empty() ? "grasp " : ", grasp ") + std::to_string(id) + " by " +
                fixed3(lag) + " m";
    }
    return grasps;
  };
  if (!in.lagging_grasps.empty()) {
    const std::string grasps = listed(in.lagging_grasps);
    warn("grasp frame faster than the pin speed limit (" + fixed3(in.pin_speed) +
         " m/s), held behind it: " + grasps);
    add("grasps behind their frame", grasps);
  }
  if (!in.stopped_grasps.empty()) {
    const std::string grasps = listed(in.stopped_grasps);
    warn("grasp stopped on the cloth under it (self-contact pushes it back), behind its "
         "frame: " + grasps);
    add("grasps stopped on the cloth", grasps);
  }
  return r;
}

}  // namespace cloth_sim::node
