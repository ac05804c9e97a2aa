// The "simulation step" status of /diagnostics from the monitor's numbers: level, message,
// key-values, stale grasp frames and grasps behind their frame merged in; the real-time factor
// window. No master.
#include <string>

#include <gtest/gtest.h>

#include "cloth_sim/node/diagnostics_report.h"

namespace cloth_sim::node {
namespace {

/// A report's value for @p key, or "(missing)".
std::string valueOf(const DiagnosticsReport& r, const std::string& key) {
  for (const auto& [k, v] : r.values) {
    if (k == key) return v;
  }
  return "(missing)";
}

/// 60 frames of 5 ms against a 1/60 s budget, on hanging.
DiagnosticsInput healthy() {
  DiagnosticsInput in;
  in.scene = "hanging";
  in.solver = "local_global";
  in.substeps = 32;
  in.iterations = 3;
  in.window.steps = 60;
  in.window.mean_time = 0.005;
  in.window.max_time = 0.0071234;
  in.window.budget = 1.0 / 60.0;
  in.real_time_factor = 0.99;
  in.sim_time = 12.5;
  in.pins = 2;
  return in;
}

TEST(DiagnosticsReport, AHealthyWindowIsOkWithEveryValueInOrder) {
  const DiagnosticsReport r = diagnosticsReport(healthy());
  EXPECT_EQ(r.level, Health::kOk);
  EXPECT_EQ(r.message, "60 steps, mean 5.00 ms of the 16.67 ms budget");
  const char* const keys[] = {"scene",
                              "solver",
                              "substeps per frame",
                              "frame budget (ms)",
                              "iterations per substep",
                              "error tolerance (m)",
                              "error estimate (m)",
                              "iteration error carried (m)",
                              "step budget (ms)",
                              "mean step time (ms)",
                              "max step time (ms)",
                              "steps",
                              "overruns",
                              "rolled-back steps",
                              "real-time factor",
                              "total overruns",
                              "total rolled-back steps",
                              "consecutive rolled-back steps",
                              "divergence resets",
                              "sim time (s)",
                              "pins",
                              "spheres",
                              "grasps",
                              "paused",
                              "frame deadline (ms)",
                              "frames cut at the deadline"};
  ASSERT_EQ(r.values.size(), std::size(keys));
  for (std::size_t k = 0; k < std::size(keys); ++k) EXPECT_EQ(r.values[k].first, keys[k]);
  EXPECT_EQ(valueOf(r, "scene"), "hanging");
  EXPECT_EQ(valueOf(r, "substeps per frame"), "32");
  EXPECT_EQ(valueOf(r, "frame budget (ms)"), "0.000");
  EXPECT_EQ(valueOf(r, "step budget (ms)"), "16.667");
  EXPECT_EQ(valueOf(r, "max step time (ms)"), "7.123");
  EXPECT_EQ(valueOf(r, "real-time factor"), "0.990");
  EXPECT_EQ(valueOf(r, "sim time (s)"), "12.500");
  EXPECT_EQ(valueOf(r, "pins"), "2");
  EXPECT_EQ(valueOf(r, "paused"), "no");
}

TEST(DiagnosticsReport, TheLevelAndMessageAreTheMonitorsAssessment) {
  DiagnosticsInput in = healthy();
  in.window.rollbacks = 3;
  EXPECT_EQ(diagnosticsReport(in).level, Health::kWarn);
  EXPECT_EQ(diagnosticsReport(in).message, assess(in.window).message);
  in.window.resets = 1;
  in.divergence_resets = 4;
  const DiagnosticsReport r = diagnosticsReport(in);
  EXPECT_EQ(r.level, Health::kError);
  EXPECT_NE(r.message.find("reset 1 time(s)"), std::string::npos) << r.message;
  EXPECT_EQ(valueOf(r, "divergence resets"), "4");
  in = healthy();
  in.window = StepWindow();
  in.paused = true;
  in.frame_budget = 0.0025;
  EXPECT_EQ(diagnosticsReport(in).level, Health::kWarn);  // no step: stalled (or paused)
  EXPECT_EQ(valueOf(diagnosticsReport(in), "paused"), "yes");
  EXPECT_EQ(valueOf(diagnosticsReport(in), "frame budget (ms)"), "2.500");
}

TEST(DiagnosticsReport, FramesCutAtTheDeadlineWarnWithTheirCount) {
  DiagnosticsInput in = healthy();
  in.frame_deadline = 0.2;
  EXPECT_EQ(valueOf(diagnosticsReport(in), "frame deadline (ms)"), "200.000");
  EXPECT_EQ(diagnosticsReport(in).level, Health::kOk);
  in.window.cut = 4;
  const DiagnosticsReport r = diagnosticsReport(in);
  EXPECT_EQ(r.level, Health::kWarn);
  EXPECT_EQ(r.message,
            "4 of 60 frames cut at the 200 ms frame deadline: the settings ask for more work than "
            "a frame can hold (fewer iterations or substeps)");
  EXPECT_EQ(valueOf(r, "frames cut at the deadline"), "4");
}

TEST(DiagnosticsReport, AHeldInputWarnsAndSaysWhich) {
  DiagnosticsInput in = healthy();
  in.notice = "pin 0: target held at (0, 0, 0.7) m: it led to 2 resets";
  const DiagnosticsReport r = diagnosticsReport(in);
  EXPECT_EQ(r.level, Health::kWarn);
  EXPECT_EQ(r.message, in.notice);
  EXPECT_EQ(valueOf(r, "held input"), in.notice);
}

TEST(DiagnosticsReport, AToleranceOutOfReachWarnsAndSaysSo) {
  DiagnosticsInput in = healthy();
  in.error_tolerance = 1e-5;
  in.error_estimate = 4e-5;
  in.carried_iteration_error = 2.5e-4;
  in.tolerance_unreachable = true;
  const DiagnosticsReport r = diagnosticsReport(in);
  EXPECT_EQ(r.level, Health::kWarn);
  EXPECT_NE(r.message.find("error tolerance needs more substeps"), std::string::npos) << r.message;
  EXPECT_EQ(valueOf(r, "error tolerance (m)"), "1e-05");
  EXPECT_EQ(valueOf(r, "error estimate (m)"), "4e-05");
  EXPECT_EQ(valueOf(r, "iteration error carried (m)"), "0.00025");
  in.tolerance_unreachable = false;
  EXPECT_EQ(diagnosticsReport(in).level, Health::kOk);
}

TEST(DiagnosticsReport, AStaleGraspFrameWarnsAndIsMergedIntoTheSummary) {
  DiagnosticsInput in = healthy();
  in.grasps = 2;
  in.stale_grasp_frames = {"gripper", "left_hand"};
  DiagnosticsReport r = diagnosticsReport(in);
  EXPECT_EQ(r.level, Health::kWarn);
  EXPECT_EQ(r.message, "grasp frame stopped updating, held at its last pose: gripper, left_hand");
  EXPECT_EQ(r.values.back().first, "stale grasp frames");
  EXPECT_EQ(r.values.back().second, "gripper, left_hand");

  in.window.rollbacks = 1;  // a warning already: both said, as mergeSummary does
  r = diagnosticsReport(in);
  EXPECT_EQ(r.level, Health::kWarn);
  EXPECT_EQ(r.message, assess(in.window).message +
                           "; grasp frame stopped updating, held at its last pose: gripper, "
                           "left_hand");
  in.window.resets = 1;  // an error stays an error
  EXPECT_EQ(diagnosticsReport(in).level, Health::kError);
}

TEST(DiagnosticsReport, AGraspBehindItsFrameWarnsWithItsLag) {
  DiagnosticsInput in = healthy();
  in.grasps = 2;
  in.pin_speed = 2.0;
  in.lagging_grasps = {{0, 0.9667}, {3, 0.0125}};
  DiagnosticsReport r = diagnosticsReport(in);
  EXPECT_EQ(r.level, Health::kWarn);
  EXPECT_EQ(r.message, "grasp frame faster than the pin speed limit (2.000 m/s), held behind it: "
                       "grasp 0 by 0.967 m, grasp 3 by 0.013 m");
  EXPECT_EQ(r.values.back().first, "grasps behind their frame");
  EXPECT_EQ(r.values.back().second, "grasp 0 by 0.967 m, grasp 3 by 0.013 m");
  in.lagging_grasps.clear();  // caught up
  r = diagnosticsReport(in);
  EXPECT_EQ(r.level, Health::kOk);
  EXPECT_EQ(valueOf(r, "grasps behind their frame"), "(missing)");
}

TEST(DiagnosticsReport, AGraspStoppedOnTheClothSaysSo) {
  DiagnosticsInput in = healthy();
  in.grasps = 1;
  in.stopped_grasps = {{2, 0.0123}};
  DiagnosticsReport r = diagnosticsReport(in);
  EXPECT_EQ(r.level, Health::kWarn);
  EXPECT_EQ(r.message, "grasp stopped on the cloth under it (self-contact pushes it back), "
                       "behind its frame: grasp 2 by 0.012 m");
  EXPECT_EQ(valueOf(r, "grasps stopped on the cloth"), "grasp 2 by 0.012 m");
  EXPECT_EQ(valueOf(r, "grasps behind their frame"), "(missing)");
  in.stopped_grasps.clear();
  EXPECT_EQ(diagnosticsReport(in).level, Health::kOk);
}

TEST(RealTimeWindow, SimulatedOverWallTimeThenANewWindow) {
  RealTimeWindow w(10.0);
  w.add(0.25);
  w.add(0.25);
  EXPECT_DOUBLE_EQ(w.take(11.0), 0.5);
  EXPECT_DOUBLE_EQ(w.take(11.0), 0.0);  // no wall time: 0, not a division by zero
  w.add(1.0);
  EXPECT_DOUBLE_EQ(w.take(11.5), 2.0);
}

}  // namespace
}  // namespace cloth_sim::node
