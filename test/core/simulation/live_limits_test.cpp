// The frame deadline (Simulation::setFrameDeadline): no setting holds a frame much longer than
// it (the node's guard: a slider at 100,000 iterations froze it for minutes), the shortfall is
// reported, and a frame that finishes in time is the same computation as without a deadline.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "cloth_sim/core/io/scene.h"
#include "cloth_sim/core/io/scene_limits.h"

namespace cloth_sim {
namespace {

/// The shipped hanging scene's cloth (32 x 32) at @p solver with @p substeps x @p iterations.
Simulation hanging(const std::string& solver, int substeps, int iterations) {
  SceneConfig scene = loadSceneFile(std::string(CLOTH_SIM_SOURCE_DIR) + "/config/scenes/hanging.yaml");
  SceneOverrides o;
  o.solver = solver;
  o.substeps = substeps;
  o.iterations = iterations;
  o.error_tolerance = 0.0;
  if (solver == "xpbd") o.integrator = Integrator::kImplicitEuler;  // it knows no other
  return makeSimulation(applyOverrides(std::move(scene), o));
}

double seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

TEST(FrameDeadline, NoSettingHoldsAFrameMuchLongerThanTheDeadline) {
  constexpr double kDeadline = 0.05;
  struct Case {
    const char* solver;
    int substeps, iterations;
  };
  // The sliders' ends: 100,000 iterations (about 5 s a frame here without a deadline) and 1,000
  // substeps; newton's iteration is a factorization.
  for (const Case& c : {Case{"local_global", 1, 100000}, Case{"local_global", 1000, 100000},
                        Case{"chebyshev", 1000, 1}, Case{"newton", 1000, 100000},
                        Case{"lbfgs", 8, 100000}, Case{"xpbd", 1000, 100000},
                        Case{"local_global_3n", 4, 100000}}) {
    SCOPED_TRACE(std::string(c.solver) + " " + std::to_string(c.substeps) + " x " +
                 std::to_string(c.iterations));
    Simulation sim = hanging(c.solver, c.substeps, c.iterations);
    sim.setFrameDeadline(kDeadline);
    double worst = 0.0;
    StepReport last;
    for (int f = 0; f < 3; ++f) {
      const double t_before = sim.state().time;
      const auto t0 = std::chrono::steady_clock::now();
      const StepReport r = sim.step();
      last = r;
      // The first frame also pays the one-time set-up (symbolic analysis, allocation), which no
      // deadline can cut; the node pays it at start.
      if (f > 0) worst = std::max(worst, seconds(t0));
      EXPECT_TRUE(r.shortfall());
      EXPECT_EQ(r.status, StepStatus::kOk) << r.message;
      EXPECT_NEAR(sim.state().time - t_before, sim.frameTime(), 1e-12);  // the whole frame
      EXPECT_TRUE(sim.state().positions.allFinite());
    }
    std::printf("[measured] %s %d x %d: longest frame %.3f s with a %.2f s deadline (last: %d "
                "substeps run, %d cut, %d merged, %d iterations, solve %.3f s)\n",
                c.solver, c.substeps, c.iterations, worst, kDeadline, last.substeps,
                last.cut_substeps, last.merged_substeps, last.total_iterations, last.solve_time);
    EXPECT_LT(worst, 0.5);  // the deadline plus one substep of one iteration, with slack
  }
}

TEST(FrameDeadline, AFrameInTimeIsTheSameComputation) {
  Simulation plain = hanging("local_global", 32, 3);
  Simulation guarded = hanging("local_global", 32, 3);
  guarded.setFrameDeadline(10.0);
  for (int f = 0; f < 30; ++f) {
    const StepReport r = guarded.step();
    plain.step();
    EXPECT_FALSE(r.shortfall());
    EXPECT_EQ(r.substeps, 32);
  }
  EXPECT_TRUE(guarded.state().positions == plain.state().positions);
  EXPECT_TRUE(guarded.state().velocities == plain.state().velocities);
}

TEST(FrameDeadline, BadDeadlinesAreRefused) {
  Simulation sim = hanging("local_global", 1, 1);
  EXPECT_THROW(sim.setFrameDeadline(-1.0), std::invalid_argument);
  EXPECT_THROW(sim.setFrameDeadline(std::nan("")), std::invalid_argument);
  EXPECT_EQ(sim.frameDeadline(), 0.0);
}

}  // namespace
}  // namespace cloth_sim

