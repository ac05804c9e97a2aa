/// @file step_monitor.h
/// Step timing against the real-time budget, rolled-back steps, and the divergence-reset
/// policy, kept apart from ROS so they can be tested alone (the node turns them into
/// diagnostics).
#pragma once

#include <cstdint>
#include <string>

namespace cloth_sim::node {

/// Step statistics since the previous StepMonitor::takeWindow().
struct StepWindow {
  int steps = 0;           ///< steps recorded
  int overruns = 0;        ///< steps that took longer than the budget
  int rollbacks = 0;       ///< steps the core rolled back (non-finite or diverged)
  int resets = 0;          ///< automatic resets after too many rollbacks in a row
  int cut = 0;             ///< frames whose work the frame deadline cut (StepReport::shortfall)
  double mean_time = 0.0;  ///< s, mean wall time per step
  double max_time = 0.0;   ///< s, longest step
  double budget = 0.0;     ///< s, the budget the steps were held against
};

/// Counts steps and decides when repeated divergence calls for a reset.
///
/// Policy: a rolled-back step leaves the simulation where it was with zero velocities; if the
/// cause persists (an explicit solver past its stability limit, a pin yanked too far), the next
/// step diverges again. After @c max_rollbacks rolled-back steps in a row the simulation is
/// reset to its initial state (pins and spheres too); the solver and the reconfigured values
/// are kept, so an unstable setting shows up as a reset every max_rollbacks steps and an
/// ERROR in the diagnostics until it is changed.
class StepMonitor {
 public:
  /// @p budget in s (the time step: a slower step cannot keep up with real time);
  /// @p max_rollbacks >= 1.
  StepMonitor(double budget, int max_rollbacks);

  /// Records one step that took @p seconds of wall time. Returns true when it was the
  /// max_rollbacks-th rolled-back step in a row: the caller must reset the simulation now.
  bool record(bool rolled_back, double seconds, bool cut = false);
  /// The reset record() just asked for was replaced by holding the input that caused it (the
  /// node's reset-loop guard): it is not counted as a reset.
  void holdInsteadOfReset();
  /// Forgets the rollbacks in a row (after a reset requested by the user).
  void clearFailures() { consecutive_failures_ = 0; }
  /// The statistics since the previous call; starts a new window.
  StepWindow takeWindow();

  double budget() const { return budget_; }
  std::uint32_t consecutiveFailures() const { return consecutive_failures_; }
  std::uint32_t divergenceResets() const { return divergence_resets_; }
  std::uint64_t totalOverruns() const { return total_overruns_; }
  std::uint64_t totalRollbacks() const { return total_rollbacks_; }

 private:
  double budget_;
  int max_rollbacks_;
  std::uint32_t consecutive_failures_ = 0;
  std::uint32_t divergence_resets_ = 0;
  std::uint64_t total_overruns_ = 0;
  std::uint64_t total_rollbacks_ = 0;
  StepWindow window_;
  double window_time_sum_ = 0.0;
};

/// Diagnostic level of a window (numerically the same as diagnostic_msgs/DiagnosticStatus).
enum class Health : std::uint8_t { kOk = 0, kWarn = 1, kError = 2 };

/// Level and one-line summary of a window.
struct HealthReport {
  Health level = Health::kOk;
  std::string message;
};

/// ERROR if the window had an automatic reset; WARN if it had no step at all (stalled), a
/// rolled-back step, or more than @p overrun_tolerance of its steps over budget (the
/// simulation runs slower than real time); OK otherwise.
HealthReport assess(const StepWindow& window, double overrun_tolerance = 0.1);

}  // namespace cloth_sim::node
