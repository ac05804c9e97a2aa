// Threads change how fast a frame is computed, never what it computes: every shipped scene and
// the solvers' kernels give the same bits at 1, 2 and 3 threads (docs/architecture.md, "Threads").
#include <algorithm>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "cloth_sim/core/io/scene.h"
#include "test_util.h"

namespace cloth_sim {
namespace {

/// What a run leaves: the state, and per frame what the report says.
struct Run {
  Points positions, velocities;
  std::vector<Vec3> sphere_centers;
  std::vector<double> max_strain;
  std::vector<int> contacts, self_contacts, intersections;
};

Run run(SceneConfig config, int threads, int frames) {
  SceneOverrides overrides;
  overrides.threads = threads;
  Simulation sim = makeSimulation(applyOverrides(std::move(config), overrides));
  Run r;
  for (int f = 0; f < frames; ++f) {
    const StepReport report = sim.step();
    EXPECT_EQ(report.status, StepStatus::kOk) << report.message;
    r.max_strain.push_back(report.max_strain);
    r.contacts.push_back(report.contacts);
    r.self_contacts.push_back(report.self_contacts);
    r.intersections.push_back(report.intersections);
  }
  r.positions = sim.state().positions;
  r.velocities = sim.state().velocities;
  for (const SphereCollider& s : sim.colliders().spheres()) r.sphere_centers.push_back(s.center);
  return r;
}

void expectSameBits(const SceneConfig& config, int frames, const std::string& what) {
  const Run one = run(config, 1, frames);
  for (int threads : {2, 3}) {
    const Run many = run(config, threads, frames);
    EXPECT_TRUE(many.positions == one.positions) << what << ", " << threads << " threads";
    EXPECT_TRUE(many.velocities == one.velocities) << what << ", " << threads << " threads";
    EXPECT_EQ(many.sphere_centers, one.sphere_centers) << what << ", " << threads << " threads";
    EXPECT_EQ(many.max_strain, one.max_strain) << what << ", " << threads << " threads";
    EXPECT_EQ(many.contacts, one.contacts) << what << ", " << threads << " threads";
    EXPECT_EQ(many.self_contacts, one.self_contacts) << what << ", " << threads << " threads";
    EXPECT_EQ(many.intersections, one.intersections) << what << ", " << threads << " threads";
  }
}

TEST(Threads, EveryShippedSceneGivesTheSameBitsOnOneTwoAndThreeThreads) {
  int scenes = 0;
  for (const auto& entry : std::filesystem::directory_iterator(test::sourcePath("config/scenes"))) {
    if (entry.path().extension() != ".yaml") continue;
    ++scenes;
    expectSameBits(loadSceneFile(entry.path().string()), 8, entry.path().stem().string());
  }
  EXPECT_GE(scenes, 10);
}

TEST(Threads, SplitSolvesAndAccelerationsGiveTheSameBitsAtEveryThreadCount) {
  // A grid large enough for the solves' split (several tasks) and the local step's blocks, with
  // each local/global solver and both factors.
  const SceneConfig hanging = loadSceneFile(test::sourcePath("config/scenes/hanging.yaml"));
  for (const std::string solver : {"local_global", "chebyshev", "anderson", "lbfgs"}) {
    for (const LinearSolver linear : {LinearSolver::kFused, LinearSolver::kFusedFloat}) {
      SceneOverrides o;
      o.resolution = 64;
      o.solver = solver;
      o.substeps = 2;
      o.iterations = 5;
      o.integrator = Integrator::kBdf2;
      o.linear_solver = linear;
      expectSameBits(applyOverrides(hanging, o), 4, solver + "/" + linearSolverName(linear));
    }
  }
}

TEST(Threads, ContactsOnALargerClothGiveTheSameBitsAtEveryThreadCount) {
  // drape at 64 x 64: sphere and ground contacts solved in the step, many contact blocks.
  SceneOverrides o;
  o.resolution = 64;
  o.substeps = 4;
  const SceneConfig drape =
      applyOverrides(loadSceneFile(test::sourcePath("config/scenes/drape.yaml")), o);
  expectSameBits(drape, 36, "drape-64");
}

TEST(Threads, TriangleSelfContactGivesTheSameBitsAtEveryThreadCount) {
  // pile (mode triangles, 3 mm) after it lands and folds: the broad phase's walk cut into jobs
  // and the pairs' start geometry in blocks list the serial pairs in the serial order.
  const SceneConfig pile = loadSceneFile(test::sourcePath("config/scenes/pile.yaml"));
  const cloth_sim::Run one = run(pile, 1, 90);
  EXPECT_GT(*std::max_element(one.self_contacts.begin(), one.self_contacts.end()), 100);
  expectSameBits(pile, 90, "pile");
}

// --- error control: several substep sizes, a factor kept for each ---------------------------

/// What an error-controlled run leaves: the state, and per frame the substeps and iterations
/// the controller and the tolerance chose.
struct ControlledRun {
  Points positions, velocities;
  std::vector<int> substeps, iterations, contacts;
};

/// Runs @p config for @p frames at @p threads; from frame @p switch_at on (if in range) at
/// @p later_threads, set through setSolverSettings (every run makes that call at that frame, so
/// the controller restarts the same way whatever the counts).
ControlledRun runControlled(const SceneConfig& config, int threads, int later_threads, int frames,
                            int switch_at) {
  SceneOverrides overrides;
  overrides.threads = threads;
  Simulation sim = makeSimulation(applyOverrides(config, overrides));
  ControlledRun r;
  for (int f = 0; f < frames; ++f) {
    if (f == switch_at) {
      SolverSettings settings = sim.solverSettings();
      settings.threads = later_threads;
      sim.setSolverSettings(settings);
    }
    const StepReport report = sim.step();
    EXPECT_EQ(report.status, StepStatus::kOk) << report.message;
    r.substeps.push_back(report.substeps);
    r.iterations.push_back(report.total_iterations);
    r.contacts.push_back(report.contacts);
  }
  r.positions = sim.state().positions;
  r.velocities = sim.state().velocities;
  return r;
}

void expectSameControlledBits(const SceneConfig& config, int frames, const std::string& what) {
  const int switch_at = frames / 2;
  const ControlledRun one = runControlled(config, 1, 1, frames, switch_at);
  // Several step sizes, so several kept factors (and BDF2's transitions between them).
  std::vector<int> sizes = one.substeps;
  std::sort(sizes.begin(), sizes.end());
  EXPECT_GE(std::unique(sizes.begin(), sizes.end()) - sizes.begin(), 2) << what;
  // 2 threads throughout; and 1 then 2, so factors made on one thread solve on two.
  for (const auto& [first, later] : {std::pair{2, 2}, std::pair{1, 2}, std::pair{2, 1}}) {
    const ControlledRun many = runControlled(config, first, later, frames, switch_at);
    const std::string label =
        what + ", " + std::to_string(first) + " then " + std::to_string(later) + " threads";
    EXPECT_TRUE(many.positions == one.positions) << label;
    EXPECT_TRUE(many.velocities == one.velocities) << label;
    EXPECT_EQ(many.substeps, one.substeps) << label;
    EXPECT_EQ(many.iterations, one.iterations) << label;
    EXPECT_EQ(many.contacts, one.contacts) << label;
  }
}

TEST(Threads, ErrorControlGivesTheSameBitsOnOneAndTwoThreads) {
  // substeps 0 and an error tolerance: the controller moves between step sizes, the local/global
  // problem keeps a factor per implicit step h_i, and the iterations stop at the tolerance.
  for (const LinearSolver linear : {LinearSolver::kFused, LinearSolver::kFusedFloat}) {
    SceneOverrides o;
    o.resolution = 48;
    o.substeps = 0;
    o.error_tolerance = 1e-5;  // 8, then 16, then up to 64 substeps
    o.integrator = Integrator::kBdf2;
    o.linear_solver = linear;
    const SceneConfig hanging =
        applyOverrides(loadSceneFile(test::sourcePath("config/scenes/hanging.yaml")), o);
    expectSameControlledBits(hanging, 30, std::string("hanging-48/") + linearSolverName(linear));
  }
  // With contacts: still contacts complete their friction after the solve (a tolerance is set).
  SceneOverrides o;
  o.substeps = 0;
  o.error_tolerance = 1e-3;
  o.integrator = Integrator::kBdf2;
  const SceneConfig drape =
      applyOverrides(loadSceneFile(test::sourcePath("config/scenes/drape.yaml")), o);
  expectSameControlledBits(drape, 40, "drape/error control");
}

}  // namespace
}  // namespace cloth_sim
