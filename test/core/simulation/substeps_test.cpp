// Substeps: a frame of time_step advanced as n implicit steps of time_step / n, with the user's
// pin and sphere moves spread over them (Simulation::step).
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "cloth_sim/core/io/scene.h"

namespace cloth_sim {
namespace {

/// A 10 x 10 hanging cloth (two corners pinned) and a sphere, a frame of 1 / @p rate s in
/// @p substeps.
SceneConfig hangingScene(int rate, int substeps, int iterations = 10) {
  return parseScene("time_step: 1/" + std::to_string(rate) + "\n" +
                        "solver: {name: local_global, iterations: " + std::to_string(iterations) +
                        ", substeps: " + std::to_string(substeps) + ", error_tolerance: 0}\n" +
                        R"(cloth: {grid: {rows: 10, cols: 10, size: [0.5, 0.5], position: [0, 0, 1]}}
material: {areal_density: 0.2, damping: 0.1, springs: {structural: 400, shear: 40, bending: 4}}
pins: [{row: 0, col: 0}, {row: 0, col: 9}]
colliders: {spheres: [{center: [0.0, -0.6, 0.8], radius: 0.1}]}
)",
                    "substeps_test");
}

double rmsDistance(const Points& a, const Points& b) {
  return std::sqrt((a - b).colwise().squaredNorm().mean());
}

TEST(Substeps, AFrameOfNSubstepsIsNStepsOfTheSmallerStep) {
  Simulation framed = makeSimulation(hangingScene(60, 4));
  Simulation fine = makeSimulation(hangingScene(240, 1));
  EXPECT_DOUBLE_EQ(framed.frameTime(), 1.0 / 60.0);
  EXPECT_DOUBLE_EQ(framed.substepTime(), 1.0 / 240.0);
  for (int f = 0; f < 20; ++f) {
    const StepReport r = framed.step();
    ASSERT_EQ(r.status, StepStatus::kOk);
    EXPECT_EQ(r.substeps, 4);
    for (int k = 0; k < 4; ++k) fine.step();
  }
  EXPECT_NEAR(framed.state().time, 20.0 / 60.0, 1e-12);
  EXPECT_LT((framed.state().positions - fine.state().positions).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(Substeps, APinMovedOnceAFrameMovesAcrossItsSubsteps) {
  // Moving a pin by d before a frame of n substeps = moving it d / n before each of n steps.
  Simulation framed = makeSimulation(hangingScene(60, 4));
  Simulation fine = makeSimulation(hangingScene(240, 1));
  framed.step();
  for (int k = 0; k < 4; ++k) fine.step();
  const Pin pin = framed.pins().pins().front();
  const Vec3 d(0.2, 0.1, 0.05);
  framed.movePin(pin.id, pin.target + d);
  framed.step();
  for (int k = 1; k <= 4; ++k) {
    fine.movePin(pin.id, pin.target + d * (k / 4.0));
    fine.step();
  }
  EXPECT_LT((framed.state().positions - fine.state().positions).cwiseAbs().maxCoeff(), 1e-12);
  // In one substep instead, the pinned particle would jump the whole way at once: a different,
  // harsher motion for the cloth around it.
  Simulation jerked = makeSimulation(hangingScene(240, 1));
  for (int k = 0; k < 4; ++k) jerked.step();
  jerked.movePin(pin.id, pin.target + d);
  for (int k = 0; k < 4; ++k) jerked.step();
  EXPECT_GT(rmsDistance(jerked.state().positions, fine.state().positions), 1e-3);
}

TEST(Substeps, AKinematicSphereMovedOnceAFrameSweepsAcrossItsSubsteps) {
  Simulation sim = makeSimulation(hangingScene(60, 4));
  Simulation swept = makeSimulation(hangingScene(60, 4));
  const SphereCollider s = sim.colliders().spheres().front();
  const Vec3 d(0.0, 0.7, 0.0);  // from 0.6 m in front of the cloth to 0.1 m behind it
  sim.moveSphere(s.id, s.center + d, Vec3::Zero());
  // The same motion as a velocity for one frame.
  swept.moveSphere(s.id, s.center, d / swept.frameTime());
  sim.step();
  swept.step();
  EXPECT_TRUE(sim.colliders().findSphere(s.id)->center.isApprox(s.center + d, 1e-12));
  EXPECT_EQ(sim.colliders().findSphere(s.id)->velocity, Vec3::Zero());
  EXPECT_LT((sim.state().positions - swept.state().positions).cwiseAbs().maxCoeff(), 1e-12);
  // It swept through the cloth's plane (y = 0 at rest) and pushed the cloth ahead: none inside.
  const Vec3 c = sim.colliders().findSphere(s.id)->center;
  const double closest = (sim.state().positions.colwise() - c).colwise().norm().minCoeff();
  EXPECT_GE(closest, s.radius - 1e-9);
}

TEST(Substeps, ARolledBackFrameKeepsTheUsersEdits) {
  SceneConfig scene = hangingScene(60, 4);
  // Explicit Euler far past its stability limit (h omega ~ 400) diverges within the frame.
  scene.options.solver = "explicit_euler";
  scene.grid.material.structural = 1e9;
  Simulation sim = makeSimulation(scene);
  const Pin pin = sim.pins().pins().front();
  const SphereCollider s = sim.colliders().spheres().front();
  const Points start = sim.state().positions;
  sim.movePin(pin.id, pin.target + Vec3(0.1, 0.0, 0.0));
  sim.moveSphere(s.id, s.center + Vec3(0.3, 0.0, 0.0), Vec3(1.0, 0.0, 0.0));
  const int added = sim.addPinHere(55);
  EXPECT_NE(sim.step().status, StepStatus::kOk);
  EXPECT_EQ(sim.state().positions, start);
  EXPECT_TRUE(sim.pins().find(pin.id)->target.isApprox(pin.target + Vec3(0.1, 0.0, 0.0)));
  EXPECT_NE(sim.pins().find(added), nullptr);
  const SphereCollider* moved = sim.colliders().findSphere(s.id);
  ASSERT_NE(moved, nullptr);
  EXPECT_TRUE(moved->center.isApprox(s.center + Vec3(0.3, 0.0, 0.0), 1e-12));
  EXPECT_EQ(moved->velocity, Vec3(1.0, 0.0, 0.0));
}

TEST(Substeps, AFarPinTargetIsApproachedAtTheSpeedLimitWithoutRollback) {
  // A target 15 m away once yanked the pin there in one frame; every frame then diverged
  // and was rolled back. Now it is approached at maxPinMove() per frame.
  Simulation sim = makeSimulation(hangingScene(60, 4));
  const Pin pin = sim.pins().pins().front();
  const double limit = sim.maxPinMove();
  EXPECT_NEAR(limit, 4 * (0.5 / 9) * 100 / 10.0, 1e-12);  // substeps x spacing x strain / 10
  const Vec3 far = pin.target + Vec3(15.0, 0.0, 0.0);
  sim.movePin(pin.id, far);
  Vec3 last = pin.target;
  for (int f = 0; f < 12; ++f) {
    ASSERT_EQ(sim.step().status, StepStatus::kOk) << "frame " << f;
    const Vec3 at = sim.state().positions.col(pin.vertex);  // a hard pin: on its moving target
    EXPECT_LE((at - last).norm(), limit * (1 + 1e-12));
    last = at;
  }
  EXPECT_EQ(sim.pins().find(pin.id)->target, far);  // the request stands
  EXPECT_LT((last - far).norm(), 1e-9);  // 15 m at 2.2 m per frame: there after 7 frames
}

TEST(Substeps, ResetClothKeepsThePinsAndSpheresTheUserAdded) {
  // The automatic reset after repeated rollbacks once wiped the user's pins and spheres.
  Simulation sim = makeSimulation(hangingScene(60, 4));
  const Points start = sim.state().positions;
  for (int f = 0; f < 10; ++f) sim.step();
  const int pin = sim.addPinHere(55);
  const Pin moved = sim.pins().pins().front();
  sim.movePin(moved.id, moved.target + Vec3(0.05, 0.0, 0.0));
  SphereCollider ball;
  ball.center = Vec3(0.0, -0.5, 0.5);
  ball.radius = 0.05;
  ball.mass = 0.01;
  ball.velocity = Vec3(0.0, 1.0, 0.0);
  const int sphere = sim.addSphere(ball);
  sim.step();
  sim.resetCloth();
  EXPECT_EQ(sim.state().positions, start);
  EXPECT_EQ(sim.state().velocities.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_NE(sim.pins().find(pin), nullptr);
  EXPECT_EQ(sim.pins().find(moved.id)->target, moved.target + Vec3(0.05, 0.0, 0.0));
  ASSERT_NE(sim.colliders().findSphere(sphere), nullptr);
  EXPECT_EQ(sim.colliders().findSphere(sphere)->velocity, Vec3::Zero());  // a ball is stopped
  EXPECT_EQ(sim.colliders().spheres().size(), 2u);
  for (int f = 0; f < 30; ++f) ASSERT_EQ(sim.step().status, StepStatus::kOk);
  // reset() is the full one: back to the scene's pins and spheres.
  sim.reset();
  EXPECT_EQ(sim.pins().find(pin), nullptr);
  EXPECT_EQ(sim.colliders().spheres().size(), 1u);
}

TEST(Substeps, ChangingThemFactorsOnceKeepsTheFrameAndTheHistory) {
  Simulation sim = makeSimulation(hangingScene(60, 1));
  sim.step();
  // A new step size is not a new model: the revision stays, the solver adds a factor for the
  // new h_i and keeps the old one (a controller going back to it refactors nothing).
  const auto revision = sim.revision();
  SolverSettings settings = sim.solverSettings();
  settings.substeps = 8;
  sim.setSolverSettings(settings);
  EXPECT_EQ(sim.revision(), revision);
  EXPECT_DOUBLE_EQ(sim.substepTime(), 1.0 / 480.0);
  const int factorizations = sim.factorizationCount();
  const double t = sim.state().time;
  sim.step();
  EXPECT_NEAR(sim.state().time - t, 1.0 / 60.0, 1e-12);
  EXPECT_EQ(sim.factorizationCount(), factorizations + 1);
  settings.substeps = 1;
  sim.setSolverSettings(settings);
  sim.step();
  EXPECT_EQ(sim.factorizationCount(), factorizations + 1);  // h = 1/60 s was kept
  // 0 chooses them by the error estimate, which needs a tolerance.
  settings.substeps = 0;
  settings.error_tolerance = 0.0;
  EXPECT_THROW(sim.setSolverSettings(settings), std::invalid_argument);
  EXPECT_EQ(sim.solverSettings().substeps, 1);
}

TEST(Substeps, ErrorAgainstTheSmallStepMotionFallsWithTheStep) {
  // Implicit Euler is first order: against the same cloth at 64 substeps, halving the step
  // should about halve the error (the ratios measured here: 2.3, 1.8, 1.8).
  const double t_end = 0.5;
  auto run = [&](int substeps) {
    Simulation sim = makeSimulation(hangingScene(60, substeps, 30));
    while (sim.state().time < t_end - 1e-9) sim.step();
    return Points(sim.state().positions);
  };
  const Points reference = run(64);
  double previous = rmsDistance(run(1), reference);
  for (int n : {2, 4, 8}) {
    const double e = rmsDistance(run(n), reference);
    std::printf("substeps %d: RMS %.3g m (%.2f x less than %d)\n", n, e, previous / e, n / 2);
    EXPECT_GT(previous / e, 1.5) << n << " substeps";
    previous = e;
  }
}

}  // namespace
}  // namespace cloth_sim
