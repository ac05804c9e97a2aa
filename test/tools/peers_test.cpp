// Bullet's implicit deformable solver runs the same model as cloth_sim (cloth_sim_bench peers,
// docs/benchmark.md, "Bullet's implicit solver side by side"): at the same step, converged, it
// lands where cloth_sim's converged implicit Euler lands (to round-off); and its distance to
// the true motion (the accuracy benchmark's reference) falls as its step shrinks, first order.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "accuracy.h"
#include "cases.h"
#include "peers.h"

namespace cloth_sim::bench {
namespace {

constexpr int kGrid = 8;

double rms(const Points& a, const Points& b) {
  return std::sqrt((a - b).colwise().squaredNorm().mean());
}

std::string scenesDir(const std::string& scene) {
  const std::string shipped = std::string(CLOTH_SIM_SOURCE_DIR) + "/config/scenes";
  return scene == "hanging" ? shipped : std::string(CLOTH_SIM_SOURCE_DIR) + "/bench/scenes";
}

/// Bullet's Newton run to convergence (its residual test far below the step's error).
BulletSettings converged(int substeps) {
  BulletSettings s;
  s.substeps = substeps;
  s.newton_iterations = 30;
  s.newton_tolerance = 1e-12;
  s.krylov_iterations = 5000;
  return s;
}

class BulletPeer : public ::testing::TestWithParam<std::string> {};

TEST_P(BulletPeer, MatchesConvergedImplicitEulerAtTheSameStep) {
  const BenchCase c = makeCase(scenesDir(GetParam()), GetParam(), kGrid);
  const int substeps = 4;
  const int frames = 15;  // 0.25 s
  const PeerRun bullet = runBullet(c.config, converged(substeps), {frames});
  ASSERT_EQ(bullet.positions.size(), 1u);

  SceneOverrides overrides;
  overrides.solver = "newton";
  overrides.substeps = substeps;
  overrides.iterations = 100;
  overrides.tolerance = 1e-12;
  overrides.integrator = Integrator::kImplicitEuler;  // hanging's own is BDF2
  Simulation sim = makeSimulation(applyOverrides(c.config, overrides));
  const Points start = sim.state().positions;
  for (int f = 0; f < frames; ++f) sim.step();
  const double moved = rms(sim.state().positions, start);
  const double apart = rms(bullet.positions.front(), sim.state().positions);
  std::printf("%s-%d, %d substeps, 0.25 s: moved %.3g m, Bullet to cloth_sim %.3g m\n",
              GetParam().c_str(), kGrid, substeps, moved, apart);
  EXPECT_LT(apart, 1e-9 * moved);  // measured 3e-14 m of 0.27 m (round-off)
}

TEST_P(BulletPeer, ApproachesTheTrueMotionAsTheStepShrinks) {
  const BenchCase c = makeCase(scenesDir(GetParam()), GetParam(), kGrid);
  AccuracyOptions o;
  o.cache_dir = "";
  const TrueMotion truth = trueMotion(c.config, c.name, {0.25, 0.5}, o);
  double previous = 0.0;
  for (int substeps : {2, 8, 32}) {
    const PeerRun run = runBullet(c.config, converged(substeps), truth.frames);
    ASSERT_EQ(run.positions.size(), truth.frames.size());
    const double error = rms(run.positions.back(), truth.positions.back()) / truth.diagonal;
    if (previous > 0.0) {
      // First order: 4x smaller step, about 4x smaller error (at least 2.5x).
      EXPECT_LT(error, previous / 2.5) << substeps << " substeps";
    }
    previous = error;
  }
  EXPECT_LT(previous, 0.01) << "32 substeps: RMS error / diagonal at 0.5 s";
}

INSTANTIATE_TEST_SUITE_P(Scenes, BulletPeer, ::testing::Values("hanging", "flag"));

}  // namespace
}  // namespace cloth_sim::bench
