/// @file diagnostics_report.h
/// What /diagnostics says about the simulation ("cloth_sim_node: simulation step"): the level,
/// the one-line message and the key-values, from the step monitor's window and the numbers the
/// node gathers. Pure: no ROS handle, no master (ClothSimNode::diagnose copies it into the
/// DiagnosticStatusWrapper).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "cloth_sim/node/step_monitor.h"

namespace cloth_sim::node {

/// Simulated time over wall time between two diagnostics reports.
class RealTimeWindow {
 public:
  /// The window starts at @p wall_start (s, any steady clock).
  explicit RealTimeWindow(double wall_start = 0.0) : start_(wall_start) {}
  /// A frame of @p sim_seconds was simulated (a rolled-back frame is not counted).
  void add(double sim_seconds) { sim_time_ += sim_seconds; }
  /// Simulated s per wall s since the window started (0 when no wall time passed); the next
  /// window starts at @p wall_now.
  double take(double wall_now);

 private:
  double start_;
  double sim_time_ = 0.0;
};

/// Everything one report is made of, gathered by the node.
struct DiagnosticsInput {
  std::string scene;                            ///< the scene's name
  std::string solver;                           ///< the solver in use
  int substeps = 0;                             ///< per frame
  int iterations = 0;                           ///< per substep
  double error_tolerance = 0.0;                 ///< m per frame (0: fixed substeps and iterations)
  double error_estimate = 0.0;                  ///< m, the last frame's (StepReport::error_estimate)
  /// m, the last frame's iteration errors carried to its end (StepReport::carried_iteration_error)
  double carried_iteration_error = 0.0;
  bool tolerance_unreachable = false;           ///< StepReport::tolerance_unreachable
  double frame_budget = 0.0;                    ///< s, ~budget_ms (0 = off)
  StepWindow window;                            ///< StepMonitor::takeWindow()
  double real_time_factor = 0.0;                ///< RealTimeWindow::take()
  std::uint64_t total_overruns = 0;             ///< StepMonitor::totalOverruns()
  std::uint64_t total_rollbacks = 0;            ///< StepMonitor::totalRollbacks()
  std::uint32_t consecutive_failures = 0;       ///< StepMonitor::consecutiveFailures()
  std::uint32_t divergence_resets = 0;          ///< StepMonitor::divergenceResets()
  double sim_time = 0.0;                        ///< s, the state's simulated time
  std::size_t pins = 0;                         ///< pins, the grasps' included
  std::size_t spheres = 0;                      ///< sphere colliders
  std::size_t grasps = 0;                       ///< grasps
  bool paused = false;                          ///< the step timer is paused (cloth/pause)
  std::vector<std::string> stale_grasp_frames;  ///< GraspFrames::staleFrames()
  /// Each grasp whose held particles are behind its frame: its id and Grasp::lag (m).
  std::vector<std::pair<int, double>> lagging_grasps;
  /// Each grasp stopped on the cloth under it (Grasp::stopped): its id and Grasp::lag (m).
  std::vector<std::pair<int, double>> stopped_grasps;
  double pin_speed = 0.0;                       ///< m/s, the pins' speed limit (0 = none)
  double frame_deadline = 0.0;                  ///< s, ~frame_deadline_ms (0 = none)
  /// What the node holds back from the user's inputs and why (ClothState::notice; "" = none).
  std::string notice;
};

/// One diagnostics status: level, message and key-values in display order.
struct DiagnosticsReport {
  Health level = Health::kOk;                               ///< the status level
  std::string message;                                      ///< the one-line summary
  std::vector<std::pair<std::string, std::string>> values;  ///< key, value
};

/// The report of @p in: assess(window) gives the level and message; a stale grasp frame raises
/// it to at least WARN and adds "grasp frame stopped updating, held at its last pose: <frames>"
/// (after "; " when the window already warned, as DiagnosticStatusWrapper::mergeSummary does);
/// a grasp behind its frame likewise, with "grasp frame faster than the pin speed limit (<v>
/// m/s), held behind it: grasp <id> by <lag> m", and a grasp stopped on the cloth under it with
/// "grasp stopped on the cloth under it (self-contact pushes it back), behind its frame: grasp
/// <id> by <lag> m".
/// Times are given in ms with 3 decimals, e.g. "step budget (ms)" "16.667".
DiagnosticsReport diagnosticsReport(const DiagnosticsInput& in);

}  // namespace cloth_sim::node
