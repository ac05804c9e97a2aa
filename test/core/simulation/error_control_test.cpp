// Error control (docs/method.md, "Error control"): the substep controller's rule, the local
// error estimate against a known local error, the error falling with the tolerance, and
// reruns that are the same to the bit.
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "cloth_sim/core/io/scene.h"
#include "cloth_sim/core/simulation/simulation.h"
#include "cloth_sim/core/simulation/step_controller.h"
#include "test_util.h"

namespace cloth_sim {
namespace {

// --- the controller's rule ---------------------------------------------------------------

/// A frame of n substeps of an order-p integrator makes E(n) = K / n^p (the law the controller
/// assumes): it settles on the smallest ladder rung that meets the tolerance with its safety
/// margin, in steps of at most kMaxGrowth, and stays there.
TEST(StepController, SettlesOnTheRungTheErrorLawAsksForAndStays) {
  for (int order : {1, 2}) {
    const double tol = 1e-5;
    const double n_star = 10.0;  // E(n_star) = tol
    const double K = tol * std::pow(n_star, order);
    StepController c(tol, order, 1, 128);
    int n = 1;
    int changes = 0;
    for (int frame = 0; frame < 200; ++frame) {
      const StepController::Decision d = c.next(n, K / std::pow(n, order));
      EXPECT_LE(d.substeps, n * StepController::kMaxGrowth);
      EXPECT_FALSE(d.capped);
      if (d.substeps != n) ++changes;
      n = d.substeps;
    }
    EXPECT_LE(K / std::pow(n, order), tol) << "order " << order;
    // The rung below would not meet the tolerance at the safety margin the controller asks.
    const int below = StepController::rungBelow(n);
    EXPECT_GT(K / std::pow(below, order), StepController::kSafety * tol * 0.999) << order;
    EXPECT_LE(changes, 3) << "order " << order << ": no flip-flop between two rungs";
  }
}

TEST(StepController, GoesDownOneRungAtATimeAfterCalmFrames) {
  const double tol = 1e-5;
  StepController c(tol, 2, 1, 128);
  // A frame error far under the tolerance at 64 substeps: the controller steps down, one rung
  // per kPatience frames, and never below the rung whose predicted error reaches half of it.
  const double K = 0.01 * tol * 64.0 * 64.0;
  int n = 64, frames = 0;
  std::vector<int> visited = {n};
  while (frames < 2000) {
    const int next = c.next(n, K / (double(n) * n)).substeps;
    ++frames;
    if (next != n) {
      EXPECT_EQ(next, StepController::rungBelow(n));
      visited.push_back(next);
    }
    n = next;
  }
  EXPECT_LE(K / (double(n) * n), tol);
  const int below = StepController::rungBelow(n);
  EXPECT_GE(K / (double(below) * below), StepController::kDownShare * tol * 0.999);
  // The first step down waited kPatience frames.
  EXPECT_GE(visited.size(), 2u);
}

TEST(StepController, SaysWhenTheMaximumCannotMeetTheTolerance) {
  StepController c(1e-6, 1, 1, 16);
  StepController::Decision d = c.next(16, 1e-3);  // would need 16 * 1000 / 0.7 substeps
  EXPECT_EQ(d.substeps, 16);
  EXPECT_TRUE(d.capped);
  c.setMaxSubsteps(4);
  d = c.next(16, 1e-9);
  EXPECT_LE(d.substeps, 4);
  EXPECT_THROW(StepController(0.0, 1, 1, 4), std::invalid_argument);
  EXPECT_THROW(StepController(1e-3, 1, 5, 4), std::invalid_argument);
  // A non-finite estimate (a rolled-back frame) counts as far over the tolerance.
  EXPECT_GT(c.next(2, std::nan("")).substeps, 2);
}

// Iterations per substep that follow the law the rule assumes: the least, plus an excess that
// falls as n^-kIterationExponent.
double iterationLaw(int n) {
  return StepController::kLeastIterations +
         40.0 * std::pow(8.0 / n, StepController::kIterationExponent);
}

TEST(StepController, TakesMoreSubstepsWhileTheIterationsConvergeSlowly) {
  const double tol = 1e-5;
  StepController c(tol, 2, 1, 128);
  // The error far under the tolerance at every count: only the iterations ask for substeps.
  int n = 8, changes = 0;
  for (int frame = 0; frame < 300; ++frame) {
    const StepController::Decision d = c.next(n, 1e-3 * tol, iterationLaw(n));
    EXPECT_FALSE(d.capped);
    EXPECT_LE(d.substeps, StepController::rungAtLeast(n + 1)) << "one rung a frame";
    if (d.substeps != n) ++changes;
    n = d.substeps;
  }
  // It settles on the first rung whose iterations are under kSlowIterations, and stays there:
  // the rung below would need more.
  EXPECT_LE(iterationLaw(n), StepController::kSlowIterations);
  EXPECT_GT(iterationLaw(StepController::rungBelow(n)), StepController::kSlowIterations);
  EXPECT_LE(changes, 8) << "no flip-flop";
  // Not past the maximum, and that is not a tolerance it cannot meet.
  StepController small(tol, 2, 1, 16);
  const StepController::Decision d = small.next(16, 1e-3 * tol, 50.0);
  EXPECT_EQ(d.substeps, 16);
  EXPECT_FALSE(d.capped);
  // Over the tolerance, the larger of the two asks.
  StepController both(tol, 2, 1, 128);
  EXPECT_EQ(both.next(16, 1.01 * tol, 50.0).substeps, 24);   // the iterations' rung
  EXPECT_EQ(both.next(16, 100.0 * tol, 3.0).substeps, 64);   // the estimate's
}

TEST(StepController, StepsDownAtTheLeastIterations) {
  // At the least iterations a substep takes, the rung down is the estimate's to decide, as
  // with no count at all.
  const double tol = 1e-5;
  StepController with(tol, 2, 1, 128), without(tol, 2, 1, 128);
  int a = 64, b = 64;
  for (int frame = 0; frame < 500; ++frame) {
    a = with.next(a, 1e-4 * tol, StepController::kLeastIterations).substeps;
    b = without.next(b, 1e-4 * tol).substeps;
    ASSERT_EQ(a, b) << "frame " << frame;
  }
  EXPECT_LT(a, 64);
}

// --- the estimate against the known local error of a linear oscillator -------------------

/// A particle on a spring of stiffness k to a hard-pinned one, no gravity, no damping,
/// displaced along the spring: x'' = -w^2 x, w^2 = k / m, whose exact flow over h from (x, v)
/// is x cos(w h) + v sin(w h) / w.
struct Oscillator {
  double k = 40.0, m = 0.1, rest = 0.5, amplitude = 0.05;
  double omega() const { return std::sqrt(k / m); }
  Simulation make(Integrator integrator, int substeps, double error_tolerance,
                  double frame_time = 1.0 / 240.0) const {
    Model model;
    model.mass = Eigen::VectorXd::Constant(2, m);
    model.springs.add(0, 1, rest, k, SpringFamily::kStructural);
    model.triangles.resize(3, 0);
    model.gravity = Vec3::Zero();
    Points x(3, 2);
    x.col(0) = Vec3::Zero();
    x.col(1) = Vec3(0, 0, -(rest + amplitude));
    PinSet pins;
    pins.add(0, Vec3::Zero(), 0.0, 2);
    SimulationOptions o;
    o.solver = "newton";  // converged steps: the error left is the integrator's alone
    o.settings.integrator = integrator;
    o.settings.substeps = substeps;
    o.settings.max_iterations = 50;
    o.settings.tolerance = 1e-13;
    o.settings.error_tolerance = error_tolerance;
    o.frame_time = frame_time;  // 1/240 s: w h = 0.083, the leading terms of the error dominate
    return Simulation(std::move(model), x, std::move(pins), Colliders(), o);
  }
};

// The iterates x_k = A [k == 0] + B r^k: the first iteration removes the initial guess's error A
// (a fast mode) and leaves a slow mode of rate r. The rate read from d_2 / d_1 would be about
// B / A (here 1e-4) and the tail estimate 1e5 times too small.
TEST(IterationError, ReadsNoRateFromTheMoveAwayFromTheInitialGuess) {
  const double a = 1.0, b = 1e-3, r = 0.9;
  auto x = [&](int k) { return (k == 0 ? a : 0.0) + b * std::pow(r, k); };
  IterationError error;
  EXPECT_TRUE(std::isinf(error.add(std::abs(x(1) - x(0)))));
  EXPECT_TRUE(std::isinf(error.add(std::abs(x(2) - x(1)))));
  for (int k = 3; k <= 6; ++k) {
    const double estimate = error.add(std::abs(x(k) - x(k - 1)));
    EXPECT_NEAR(estimate, x(k), 1e-12 * b) << "after change " << k;  // the exact geometric tail
  }
}

TEST(IterationError, AZeroChangeIsTheFixedPointAndAStallIsNeverDone) {
  IterationError at_rest;
  EXPECT_EQ(at_rest.add(0.0), 0.0);
  IterationError stalled;
  stalled.add(1.0);
  stalled.add(1.0);
  // The rate is capped at kMaxRate: a change that does not shrink leaves 19 changes to go.
  EXPECT_NEAR(stalled.add(1.0), IterationError::kMaxRate / (1.0 - IterationError::kMaxRate), 1e-12);
}

TEST(ErrorEstimate, WithinAFactorOfThreeOfTheTrueLocalErrorOfAnOscillator) {
  const Oscillator osc;
  const double w = osc.omega();
  for (Integrator integrator : {Integrator::kImplicitEuler, Integrator::kBdf2}) {
    // One fixed substep a frame: the estimate is reported, and a tiny tolerance converges it.
    Simulation sim = osc.make(integrator, 1, 1e-9);
    // Over a period and a half: the estimate of each step against the distance from the
    // exact flow from that step's start. Pointwise the two part where the acceleration changes
    // sign (the estimate's leading term vanishes there, the next one does not), so the figure is
    // the ratio of their sums, and every step's estimate within 3x once the truth is not tiny.
    double estimated = 0.0, true_error = 0.0, worst_ratio = 1.0, largest = 0.0;
    std::vector<std::pair<double, double>> steps;
    for (int f = 0; f < 160; ++f) {
      const double z = sim.state().positions(2, 1) + osc.rest;  // displacement from rest
      const double v = sim.state().velocities(2, 1);
      const double h = sim.frameTime();
      const double exact = z * std::cos(w * h) + v * std::sin(w * h) / w;
      const StepReport r = sim.step();
      ASSERT_EQ(r.status, StepStatus::kOk);
      // The RMS over the free particles of a one-particle cloth is that particle's error.
      const double truth = std::abs(sim.state().positions(2, 1) + osc.rest - exact);
      if (f < 3) continue;  // BDF2's first steps start from Euler's history
      estimated += r.error_estimate;
      true_error += truth;
      largest = std::max(largest, truth);
      steps.emplace_back(r.error_estimate, truth);
    }
    for (const auto& [estimate, truth] : steps) {
      if (truth < 0.3 * largest) continue;
      worst_ratio = std::max(worst_ratio, std::max(estimate / truth, truth / estimate));
    }
    std::printf("[measured] %s, h = 1/240 s, w h = %.3f: sum of estimates / sum of true local "
                "errors %.2f; worst step (true error over 30 %% of the largest) %.2f x\n",
                integratorName(integrator), w / 240.0, estimated / true_error, worst_ratio);
    EXPECT_GT(estimated / true_error, 1.0 / 3.0) << integratorName(integrator);
    EXPECT_LT(estimated / true_error, 3.0) << integratorName(integrator);
    EXPECT_LT(worst_ratio, 3.0) << integratorName(integrator);
  }
}

// The frame's estimate sums its substeps' errors per particle as vectors (FrameError). Along a
// motion slower than the frame they point the same way and add up to the sum of their sizes;
// over a vibration faster than the frame they turn with it and cancel.
TEST(ErrorEstimate, AddsAlongASlowMotionAndCancelsOverAVibrationFasterThanTheFrame) {
  const Oscillator osc;  // w = 20 rad/s
  const double h = 1.0 / 960.0;
  for (const int n : {8, 960}) {  // frames of w F = 0.17 rad and of 20 rad (3.2 periods)
    // The same steps, one frame each: their own estimates, summed over each frame of n.
    Simulation steps = osc.make(Integrator::kBdf2, 1, 1e-9, h);
    Simulation frames = osc.make(Integrator::kBdf2, n, 1e-9, n * h);
    double summed_sizes = 0.0, frame_estimates = 0.0;
    for (int f = 0; f < 3; ++f) {
      const StepReport r = frames.step();
      ASSERT_EQ(r.status, StepStatus::kOk);
      for (int k = 0; k < n; ++k) {
        const StepReport one = steps.step();
        if (f > 0) summed_sizes += one.error_estimate;  // BDF2's first steps start as Euler
      }
      if (f > 0) frame_estimates += r.error_estimate;
    }
    EXPECT_NEAR((steps.state().positions - frames.state().positions).norm(), 0.0, 1e-9);
    const double ratio = frame_estimates / summed_sizes;
    std::printf("[measured] %d substeps a frame (w F = %.2f rad): frame estimates / summed step "
                "estimates %.3f\n", n, osc.omega() * n * h, ratio);
    EXPECT_LE(ratio, 1.0 + 1e-9) << "never above the sum of the sizes";
    if (n == 8) {
      EXPECT_GT(ratio, 0.9) << "slow: they add";
    } else {
      EXPECT_LT(ratio, 0.2) << "fast: they cancel";
    }
  }
}

// --- the error falls with the tolerance; reruns are the same --------------------------------

SceneConfig flagScene() {
  return parseScene(R"(time_step: 1/60
solver: {error_tolerance: 1e-4}
cloth: {grid: {rows: 10, cols: 16, size: [0.8, 0.5], position: [0.4, 0.0, 1.5]}}
material: {areal_density: 0.2, damping: 0.1, springs: {structural: 400, shear: 40, bending: 4}}
pins: [{edge: left}]
)",
                    "flag");
}

Points runFor(SceneConfig scene, double seconds, int* substeps_seen = nullptr) {
  Simulation sim = makeSimulation(scene);
  while (sim.state().time < seconds - 1e-9) {
    const StepReport r = sim.step();
    EXPECT_EQ(r.status, StepStatus::kOk);
    if (substeps_seen != nullptr) *substeps_seen = std::max(*substeps_seen, r.substeps);
  }
  return sim.state().positions;
}

double rms(const Points& a, const Points& b) {
  return std::sqrt((a - b).colwise().squaredNorm().mean());
}

TEST(ErrorControl, ATighterToleranceGivesASmallerErrorAgainstTheSmallStepMotion) {
  SceneConfig reference = flagScene();
  reference.options.settings.error_tolerance = 0.0;
  reference.options.settings.substeps = 256;
  reference.options.settings.max_iterations = 100;
  reference.options.settings.tolerance = 1e-10;
  reference.options.settings.integrator = Integrator::kBdf2;
  reference.given = SolverFieldsGiven{true, true, true, true};
  const Points truth = runFor(reference, 0.5);
  double previous = 1e300;
  for (double tol : {1e-3, 1e-4, 1e-5, 1e-6}) {
    SceneConfig s = flagScene();
    s.options.settings.error_tolerance = tol;
    int most = 0;
    const double e = rms(runFor(s, 0.5, &most), truth);
    std::printf("[measured] error tolerance %g m: RMS %.3g m at 0.5 s, at most %d substeps\n",
                tol, e, most);
    EXPECT_LT(e, previous) << "tolerance " << tol;
    previous = e;
  }
}

TEST(ErrorControl, ARerunIsTheSameToTheBit) {
  const SceneConfig s = flagScene();
  EXPECT_EQ(runFor(s, 1.0), runFor(s, 1.0));
  // And after a reset, the same run again.
  Simulation sim = makeSimulation(s);
  for (int f = 0; f < 30; ++f) sim.step();
  const Points first = sim.state().positions;
  sim.reset();
  for (int f = 0; f < 30; ++f) sim.step();
  EXPECT_EQ(sim.state().positions, first);
  // And from a snapshot: the substeps and the controller go on as they would have.
  const SimulationSnapshot saved = sim.snapshot();
  std::vector<int> substeps;
  for (int f = 0; f < 40; ++f) substeps.push_back(sim.step().substeps);
  const Points after = sim.state().positions;
  sim.restore(saved);
  for (int f = 0; f < 40; ++f) EXPECT_EQ(sim.step().substeps, substeps[f]) << "frame " << f;
  EXPECT_EQ(sim.state().positions, after);
}

// --- the iteration error a frame carries to its end ------------------------------------------

/// The iterations' part of a frame's error, measured: the frame run from the same state with
/// the iterations stopped at the tolerance and converged (1e-6 of it), at the same substeps.
/// The substeps' own iteration errors (the stop's reading) are far under it: each substep's
/// error also moves the rest of the frame (StepReport::carried_iteration_error), and the stop
/// reads the slow modes' rate low. Measured on this flag at 16 substeps: the largest substep's
/// error 1/1000 to 1/400 of the truth, the carried sum 0.11x to 0.27x. What is asserted: the
/// carried sum within 10x under and 3x over the truth on every probed frame, and the largest
/// substep's alone over 30x under it.
TEST(ErrorEstimate, TheCarriedIterationErrorIsWithinTenTimesTheIterationsOwn) {
  SceneConfig loose = flagScene();
  loose.options.settings.error_tolerance = 1e-5;
  loose.options.settings.substeps = 16;  // fixed: both runs take the same steps
  loose.given.substeps = true;
  SceneConfig tight = loose;
  tight.options.settings.error_tolerance = 1e-11;
  tight.options.settings.max_iterations = 5000;
  Simulation a = makeSimulation(loose), b = makeSimulation(tight);
  std::vector<char> free(a.model().particleCount(), 1);
  for (const Pin& p : a.pins().pins()) free[p.vertex] = 0;
  for (int frame = 1; frame <= 40; ++frame) {
    const bool probed = frame % 8 == 0;
    if (probed) {
      b.restore(a.snapshot());  // the state, and the loose settings: the tight ones again
      b.setSolverSettings(tight.options.settings);
    }
    const StepReport r = a.step();
    ASSERT_EQ(r.status, StepStatus::kOk);
    if (!probed) continue;
    ASSERT_EQ(b.step().substeps, r.substeps);
    double sum = 0.0;
    int count = 0;
    for (Eigen::Index i = 0; i < a.model().particleCount(); ++i) {
      if (!free[i]) continue;
      sum += (a.state().positions.col(i) - b.state().positions.col(i)).squaredNorm();
      ++count;
    }
    const double truth = std::sqrt(sum / count);
    std::printf("[measured] frame %d: iterations' error %.3g m, carried estimate %.3g m (%.2fx), "
                "largest substep's %.3g m (%.4fx)\n",
                frame, truth, r.carried_iteration_error, r.carried_iteration_error / truth,
                r.iteration_error, r.iteration_error / truth);
    EXPECT_GT(r.carried_iteration_error, truth / 10.0) << "frame " << frame;
    EXPECT_LT(r.carried_iteration_error, truth * 3.0) << "frame " << frame;
    EXPECT_LT(r.iteration_error, truth / 30.0) << "frame " << frame;
  }
}

// --- a frame far over the tolerance is run again ----------------------------------------------

/// A 0.5 m sheet pinned on every edge with a still sphere pressed 7 cm into it, at the scene
/// format's default (error control), or at @p substeps fixed ones (0: automatic) with the
/// same tolerance. The overlap is moved out of at the start and the springs snap back in the
/// first frame: a transient the first frame's 8 substeps cannot follow.
SceneConfig snapScene(int substeps) {
  SceneConfig s = parseScene(R"(time_step: 1/60
cloth: {grid: {rows: 12, cols: 12, size: [0.5, 0.5], position: [0.0, 0.0, 1.0]}}
material: {areal_density: 0.2, damping: 0.5, springs: {structural: 400, shear: 40}}
pins: [{edge: all}]
colliders: {spheres: [{center: [0.0, 0.0, 1.03], radius: 0.1}]}
)",
                             "snap");
  if (substeps > 0) {
    s.options.settings.substeps = substeps;
    s.given.substeps = true;
  }
  return s;
}

TEST(ErrorControl, AFrameFarOverTheToleranceIsRunAgainWithMoreSubsteps) {
  Simulation sim = makeSimulation(snapScene(0));
  const StepReport first = sim.step();
  ASSERT_EQ(first.status, StepStatus::kOk);
  std::printf("[measured] first frame: %d substeps kept, %d rejected, estimate %.3g m (%.1fx "
              "the tolerance)\n",
              first.substeps, first.rejected_substeps, first.error_estimate,
              first.error_estimate / first.error_tolerance);
  EXPECT_GT(first.rejected_substeps, 0);
  EXPECT_GT(first.substeps, Simulation::kFirstAutomaticSubsteps);
  EXPECT_TRUE(first.error_estimate <= Simulation::kRedoShare * first.error_tolerance ||
              first.substeps == sim.substepLimit());
  // The frame kept is closer to the converged motion than the one at the first substeps.
  SceneConfig converged = snapScene(512);
  converged.options.settings.error_tolerance = 0.0;
  converged.options.settings.max_iterations = 200;
  converged.options.settings.tolerance = 1e-10;
  converged.options.settings.integrator = Integrator::kBdf2;
  converged.given = SolverFieldsGiven{true, true, true, true};
  Simulation truth = makeSimulation(converged);
  truth.step();
  SceneConfig fixed = snapScene(Simulation::kFirstAutomaticSubsteps);
  fixed.options.settings.error_tolerance = first.error_tolerance;  // the same iterations' stop
  fixed.options.settings.integrator = Integrator::kBdf2;
  fixed.given.error_tolerance = true;
  Simulation first_try = makeSimulation(fixed);
  first_try.step();
  const double kept = rms(sim.state().positions, truth.state().positions);
  const double rejected = rms(first_try.state().positions, truth.state().positions);
  std::printf("[measured] RMS against the converged frame: %.3g m kept, %.3g m at %d substeps\n",
              kept, rejected, Simulation::kFirstAutomaticSubsteps);
  EXPECT_LT(kept, 0.5 * rejected);
}

}  // namespace
}  // namespace cloth_sim
