// Self-contact in whole scenes (docs/testing.md, "Self-contact"): the shipped fold and pile
// scenes (mode triangles, 3 mm thick), the particle mode's randomized set of folds and drops
// (fixed, printed seeds; the triangle mode's own set is self_contact_thin_scenes_test), the
// option off giving bit-identical trajectories, and the recovery from tangles. Every step must leave no intersecting pair of non-adjacent
// triangles (IntersectionCounter), and at rest no particle may be closer than t/2 to a triangle
// of another layer (a triangle whose vertices are all more than 2 t away from it on the cloth
// at rest, so that the bend of a fold does not count as two layers).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "cloth_sim/core/collision/cell_hash.h"
#include "cloth_sim/core/collision/contact_projection.h"
#include "cloth_sim/core/io/scene.h"
#include "cloth_sim/core/io/scene_overrides.h"
#include "test_util.h"

namespace cloth_sim {
namespace {

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

/// Smallest distance (m) from a particle to a triangle of another layer, capped at @p cap.
double minLayerDistance(const Simulation& sim, const Points& rest, double thickness, double cap) {
  const Points& x = sim.state().positions;
  const Eigen::Matrix3Xi& tri = sim.model().triangles;
  CellHash hash;
  hash.build(x, cap);
  double best = cap;
  const double far = 2.0 * thickness;
  for (Eigen::Index t = 0; t < tri.cols(); ++t) {
    const Vec3 a = x.col(tri(0, t)), b = x.col(tri(1, t)), c = x.col(tri(2, t));
    Eigen::AlignedBox3d box(a);
    box.extend(b).extend(c);
    const Vec3 reach = Vec3::Constant(cap);
    hash.query(Eigen::AlignedBox3d(box.min() - reach, box.max() + reach), [&](int i) {
      for (int k = 0; k < 3; ++k) {
        if ((rest.col(i) - rest.col(tri(k, t))).norm() <= far) return;
      }
      best = std::min(best, (closestPointOnTriangle(x.col(i), a, b, c) - x.col(i)).norm());
    });
  }
  return best;
}

/// The pin's target at time @p time of a fold: from @p from over an arc @p lift high to
/// @p to, raised by two @p thickness (on the lower layer and the flap trailing under the
/// corner: held at one, the pin squeezes the flap against the ground), in @p duration s.
Vec3 foldTarget(const Vec3& from, const Vec3& to, double lift, double thickness, double duration,
                double time) {
  const double s = std::min(1.0, time / duration);
  const double along = 0.5 * (1.0 - std::cos(M_PI * s));
  return from + along * (to - from) + Vec3(0, 0, lift * std::sin(M_PI * s) + 2.0 * thickness * along);
}

struct RunResult {
  int steps = 0;
  int max_intersections = 0;
  int failed_steps = 0;
  double min_layer_distance = 0.0;
  double thickness = 0.0;
  double max_speed = 0.0;
};

/// Runs @p sim: @p fold_frames frames of a fold of pin @p pin (if >= 0) towards vertex
/// @p to_vertex, then the pin removed and @p settle_frames frames more.
RunResult run(Simulation& sim, int pin, int to_vertex, double lift, int fold_frames,
              int settle_frames) {
  RunResult r;
  const Points rest = sim.state().positions;
  r.thickness = sim.selfContact()->thickness();
  const double dt = sim.frameTime();
  Vec3 from = Vec3::Zero(), to = Vec3::Zero();
  if (pin >= 0) {
    from = sim.pins().find(pin)->target;
    to = rest.col(to_vertex);
  }
  for (int k = 1; k <= fold_frames + settle_frames; ++k) {
    if (pin >= 0 && k <= fold_frames) {
      sim.movePin(pin, foldTarget(from, to, lift, r.thickness, fold_frames * dt, k * dt));
    }
    if (pin >= 0 && k == fold_frames + 1) sim.removePin(pin);
    const StepReport report = sim.step();
    ++r.steps;
    r.failed_steps += report.status != StepStatus::kOk;
    r.max_intersections = std::max(r.max_intersections, report.intersections);
    EXPECT_GE(report.intersections, 0);
  }
  r.max_speed = sim.state().velocities.colwise().norm().maxCoeff();
  r.min_layer_distance = minLayerDistance(sim, rest, r.thickness, r.thickness);
  return r;
}

void expectClean(const RunResult& r, const std::string& what) {
  std::printf(
      "%s: %d steps, max intersecting pairs %d, failed steps %d, min layer distance "
      "%.4f m = %.2f t (t = %.4f m), max speed at the end %.3f m/s\n",
      what.c_str(), r.steps, r.max_intersections, r.failed_steps, r.min_layer_distance,
      r.min_layer_distance / r.thickness, r.thickness, r.max_speed);
  EXPECT_EQ(r.max_intersections, 0) << what;
  EXPECT_EQ(r.failed_steps, 0) << what;
  EXPECT_GE(r.min_layer_distance, 0.5 * r.thickness) << what;
}

TEST(SelfContactScenes, FoldLeavesTwoLayersApartWithoutIntersecting) {
  Simulation sim = makeSimulation(loadSceneFile(test::sourcePath("config/scenes/fold.yaml")));
  ASSERT_NE(sim.selfContact(), nullptr);
  const int pin = sim.pins().pins().front().id;
  const int corner = sim.pins().pins().front().vertex, opposite = sim.model().particleCount() - 1;
  const RunResult r = run(sim, pin, opposite, 0.35, 90, 90);  // 1.5 s fold, 1.5 s to settle
  expectClean(r, "fold");
  // It did fold: the corner came down by the opposite corner, and about half the cloth lies
  // one layer up (at 3 mm the corner itself may slip off the lower layer's edge onto the floor).
  const Points& x = sim.state().positions;
  const Vec3 c = x.col(corner), o = x.col(opposite);
  EXPECT_LT((c - o).head<2>().norm(), 0.15);
  const double upper = (x.row(2).array() > 0.5 * r.thickness).cast<double>().mean();
  std::printf("fold: %.0f %% of the particles lie on the other layer\n", 100.0 * upper);
  EXPECT_GT(upper, 0.3);
}

TEST(SelfContactScenes, PileFallsInFoldsWithoutIntersecting) {
  Simulation sim = makeSimulation(loadSceneFile(test::sourcePath("config/scenes/pile.yaml")));
  const RunResult r = run(sim, -1, -1, 0.0, 0, 180);  // 3 s
  expectClean(r, "pile");
  // It did pile up: 1.8 m of cloth now lower than a third of that, in several layers.
  const Points& x = sim.state().positions;
  EXPECT_LT(x.row(2).maxCoeff(), 0.6);
  EXPECT_GT(sim.selfContact()->thickness(), 0.0);
}

/// @p yaml with self_collision: {enabled: false} appended and without: the same trajectory,
/// bit for bit.
void expectOffIsAbsent(const std::string& scene) {
  const std::string path = test::sourcePath("config/scenes/" + scene + ".yaml");
  const std::string text = readFile(path);
  ASSERT_EQ(text.find("self_collision"), std::string::npos);
  Simulation absent = makeSimulation(parseScene(text, path));
  Simulation off = makeSimulation(
      parseScene(text + "\nself_collision: {enabled: false, thickness: 0.01}\n", path));
  for (int k = 0; k < 40; ++k) {
    const StepReport a = absent.step(), b = off.step();
    EXPECT_EQ(a.intersections, -1);
    EXPECT_EQ(b.intersections, -1);
  }
  EXPECT_TRUE(absent.state().positions == off.state().positions) << scene;
  EXPECT_TRUE(absent.state().velocities == off.state().velocities) << scene;
}

/// The fold's corner driven down onto the far corner itself, under the default's error control
/// (24 x 24 to stay quick), by its pin or by a grasp: the flap that trails under it and the
/// lower layer are in the way. The pin or gripper must stop on them (FrameInputs::pinsAt,
/// GraspSet::place): driven on, it squeezed them against the ground and they were pushed out
/// sideways (with the pin: max strain 53, 35 intersecting pairs, the corner 0.36 m under the far
/// corner's height).
void driveIntoTheStack(bool grasp) {
  const std::string path = test::sourcePath("config/scenes/fold.yaml");
  std::istringstream in(readFile(path));
  std::string text, line;
  bool solver = false;  // the scene without its solver block: the default, error control
  while (std::getline(in, line)) {
    if (line.rfind("solver:", 0) == 0) solver = true;
    else if (!line.empty() && line[0] != ' ') solver = false;
    if (!solver) text += line + "\n";
  }
  SceneOverrides resolution;
  resolution.resolution = 24;
  Simulation sim = makeSimulation(applyOverrides(parseScene(text, path), resolution));
  ASSERT_GT(sim.options().settings.error_tolerance, 0.0);
  const Pin pin = sim.pins().pins().front();
  const int corner = pin.vertex, far = sim.model().particleCount() - 1;
  const Vec3 from = pin.target, to = sim.state().positions.col(far);
  const double t = sim.selfContact()->thickness(), dt = sim.frameTime();
  const auto target = [&](double time) { return foldTarget(from, to, 0.3, 0.0, 60 * dt, time); };
  int held = -1;
  if (grasp) {
    sim.removePin(pin.id);
    held = sim.addGrasp({corner}, Pose(Eigen::Translation3d(from)));
    sim.setGraspPoseSource([&](int, double time) { return Pose(Eigen::Translation3d(target(time))); });
  }
  double max_strain = 0.0;
  int max_intersections = 0, failed = 0;
  for (int frame = 1; frame <= 90; ++frame) {  // 1 s of fold, held 0.25 s, let go
    if (!grasp && frame <= 75) sim.movePin(pin.id, target(frame * dt));
    if (frame == 76) grasp ? sim.removeGrasp(held) : sim.removePin(pin.id);
    const StepReport r = sim.step();
    failed += r.status != StepStatus::kOk;
    max_intersections = std::max(max_intersections, r.intersections);
    max_strain = std::max(max_strain, r.max_strain);
    if (frame == 75) {
      const double above = sim.state().positions(2, corner) - sim.state().positions(2, far);
      std::printf("%s driven into the stack: held %.4f m above the far corner (t = %.4f m)\n",
                  grasp ? "grasp" : "pin", above, t);
      EXPECT_GT(above, t) << "it stopped on the layers below";
    }
  }
  std::printf("%s driven into the stack: max strain %.3f, max intersecting pairs %d, failed "
              "frames %d\n", grasp ? "grasp" : "pin", max_strain, max_intersections, failed);
  EXPECT_EQ(failed, 0);
  EXPECT_EQ(max_intersections, 0);
  EXPECT_LT(max_strain, 0.4) << "nothing squeezed out";
}

TEST(SelfContactScenes, APinDrivenIntoTheStackBelowStopsOnIt) { driveIntoTheStack(false); }

TEST(SelfContactScenes, AGripperDrivenIntoTheStackBelowStopsOnIt) { driveIntoTheStack(true); }

TEST(SelfContactScenes, OptionOffGivesBitIdenticalTrajectories) {
  for (const char* scene : {"hanging", "drape", "gravity_well", "tablecloth"}) {
    SCOPED_TRACE(scene);
    expectOffIsAbsent(scene);
  }
}

TEST(SelfContactScenes, WorksWithSpheresDynamicBallsAndMeshObstacles) {
  // drape (a sphere and the ground, contact in the solve), gravity_well (dynamic balls rolling
  // on the sheet) and tablecloth (a mesh cloth on a mesh table) with self-collision on at the
  // automatic thickness: 2 s each.
  for (const char* scene : {"drape", "gravity_well", "tablecloth"}) {
    SCOPED_TRACE(scene);
    const std::string path = test::sourcePath("config/scenes/" + std::string(scene) + ".yaml");
    Simulation sim = makeSimulation(parseScene(readFile(path) + "\nself_collision: {}\n", path));
    int max_intersections = 0, failed = 0;
    for (int k = 0; k < 120; ++k) {
      const StepReport r = sim.step();
      max_intersections = std::max(max_intersections, r.intersections);
      failed += r.status != StepStatus::kOk;
    }
    std::printf("%s with self-collision (t = %.4f m): max intersecting pairs %d, failed steps %d\n",
                scene, sim.selfContact()->thickness(), max_intersections, failed);
    EXPECT_EQ(max_intersections, 0);
    EXPECT_EQ(failed, 0);
    const GroundPlane& ground = sim.colliders().ground();
    if (ground.enabled) {  // the ground has the last word over self-contact
      EXPECT_GE(sim.state().positions.row(2).minCoeff(), ground.height - 1e-9);
    }
  }
}

/// A random fold or drop: size, resolution, height, lean, fold path. Built from YAML text, as a
/// scene file would be.
std::string randomScene(std::mt19937& rng, bool pile, double& thickness) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::ostringstream y;
  y << "time_step: 1/60\nmaterial:\n  areal_density: 0.2\n  damping: 0.1\n"
       "  springs: {structural: 400, shear: 40, bending: 4}\n"
       "colliders:\n  ground: {height: 0.0, friction: 0.5}\n";
  if (pile) {
    const int cols = 10 + static_cast<int>(u(rng) * 12), rows = 30 + static_cast<int>(u(rng) * 30);
    const double width = 0.3 + 0.4 * u(rng), length = 0.9 + 0.9 * u(rng);
    const double spacing = std::max(width / (cols - 1), length / (rows - 1));
    const double drop = 0.05 + 0.45 * u(rng), lean = 0.05 + 0.2 * u(rng), yaw = 6.0 * u(rng);
    thickness = 1.1 * spacing;
    y << "cloth:\n  grid: {rows: " << rows << ", cols: " << cols << ", size: [" << width << ", "
      << length << "], position: [0, 0, " << drop + 0.5 * length * std::cos(lean) + 0.5 * width * 0
      << "], orientation_rpy: [" << M_PI / 2 - lean << ", 0, " << yaw << "]}\n";
  } else {
    const int n = 16 + static_cast<int>(u(rng) * 17);
    const double size = 0.6 + 0.6 * u(rng);
    thickness = 1.1 * size / (n - 1);
    y << "cloth:\n  grid: {rows: " << n << ", cols: " << n << ", size: [" << size << ", " << size
      << "]}\npins:\n  - {row: 0, col: 0}\n";
  }
  y << "self_collision: {mode: particles, thickness: " << thickness << ", friction: "
    << 0.5 * u(rng) << "}\n";
  return y.str();
}

TEST(SelfContactRandom, FoldsAndDropsNeverIntersect) {
  const unsigned first_seed = 20261123;
  for (unsigned k = 0; k < 20; ++k) {
    const unsigned seed = first_seed + k;
    std::mt19937 rng(seed);
    const bool pile = k % 2 == 1;
    double thickness = 0.0;
    const std::string yaml = randomScene(rng, pile, thickness);
    std::printf("seed %u (%s):\n%s", seed, pile ? "pile" : "fold", yaml.c_str());
    SCOPED_TRACE("seed " + std::to_string(seed));
    Simulation sim = makeSimulation(parseScene(yaml, "random_" + std::to_string(seed)));
    RunResult r;
    std::uniform_real_distribution<double> u(0.0, 1.0);
    if (pile) {
      r = run(sim, -1, -1, 0.0, 0, 150);
    } else {
      const int n = static_cast<int>(std::lround(std::sqrt(sim.model().particleCount())));
      // To the opposite corner (diagonal fold) or the next corner along a side (folded in half).
      const int to = u(rng) < 0.5 ? n * n - 1 : n * (n - 1);
      const double lift = (0.2 + 0.3 * u(rng)) * std::sqrt(sim.model().particleCount()) * thickness;
      const int frames = 60 + static_cast<int>(u(rng) * 90);
      r = run(sim, sim.pins().pins().front().id, to, lift, frames, 90);
    }
    expectClean(r, "seed " + std::to_string(seed));
  }
}

// Recovery from a tangle (docs/method.md, "Self-contact", "Tangles"). The hanging cloth of
// 20 x 20 (1 m, two top corners pinned; four for the balls), 8 substeps of 2 iterations.
std::string tangleScene(bool four_corners, bool self_collision) {
  std::string yaml = R"(
time_step: 1/60
solver: {name: local_global, iterations: 2, substeps: 8}
cloth:
  grid: {rows: 20, cols: 20, size: [1.0, 1.0], position: [0.0, 0.0, 1.5]}
material:
  areal_density: 0.2
  damping: 0.1
  springs: {structural: 400, shear: 40, bending: 4}
pins:
  - {row: 0, col: 0}
  - {row: 0, col: 19}
)";
  if (four_corners) yaml += "  - {row: 19, col: 0}\n  - {row: 19, col: 19}\n";
  if (self_collision) yaml += "self_collision: {friction: 0.3}\n";
  return yaml;
}

struct TangleRun {
  double final_strain = 0.0;
  int max_intersections = 0, final_intersections = 0, failed_steps = 0;
};

/// Steps @p sim @p frames times, @p before called before each step with the frame number.
template <typename Before>
TangleRun runTangle(Simulation& sim, int frames, Before&& before) {
  TangleRun r;
  for (int k = 1; k <= frames; ++k) {
    before(k);
    const StepReport report = sim.step();
    r.failed_steps += report.status != StepStatus::kOk;
    r.max_intersections = std::max(r.max_intersections, sim.countIntersections());
    r.final_strain = report.max_strain;
  }
  r.final_intersections = sim.countIntersections();
  return r;
}

TEST(TangleRecovery, PinJumpedOneMetreAndBackLeavesNoCrease) {
  // A corner pin jumps 1 m down in one message after 1 s, and back after 2 s; 6 s in all. The
  // same cloth left alone gives the strain it should come back to.
  for (const bool self : {false, true}) {
    Simulation quiet = makeSimulation(parseScene(tangleScene(false, self), "tangle"));
    const TangleRun base = runTangle(quiet, 360, [](int) {});
    Simulation sim = makeSimulation(parseScene(tangleScene(false, self), "tangle"));
    const int pin = sim.pins().pins().front().id;
    const Vec3 home = sim.pins().find(pin)->target;
    const TangleRun r = runTangle(sim, 360, [&](int k) {
      if (k == 60) sim.movePin(pin, home + Vec3(0, 0, -1.0));
      if (k == 120) sim.movePin(pin, home);
    });
    std::printf(
        "pin jump, self-collision %s: final max strain %.3f (left alone: %.3f), "
        "intersecting pairs max %d, at the end %d, failed steps %d\n",
        self ? "on" : "off", r.final_strain, base.final_strain, r.max_intersections,
        r.final_intersections, r.failed_steps);
    if (!self) continue;  // off: measured and documented, not asserted (see method.md)
    EXPECT_EQ(r.max_intersections, 0);
    EXPECT_EQ(r.failed_steps, 0);
    EXPECT_LT(r.final_strain, 1.2 * base.final_strain + 0.02);
  }
}

TEST(TangleRecovery, TwoHundredBallsDroppedThroughTheClothLeaveNoCrease) {
  // 200 balls of 1.5 cm (smaller than the 5 cm spacing: they push through) dropped at 3 m/s
  // onto the cloth held by its four corners, one every other frame; those left are taken away
  // at 8 s, and the cloth has 2 s to settle.
  for (const bool self : {false, true}) {
    Simulation quiet = makeSimulation(parseScene(tangleScene(true, self), "balls"));
    const TangleRun base = runTangle(quiet, 600, [](int) {});
    Simulation sim = makeSimulation(parseScene(tangleScene(true, self), "balls"));
    std::mt19937 rng(12);
    std::uniform_real_distribution<double> u(-0.45, 0.45);
    int spawned = 0;
    const TangleRun r = runTangle(sim, 600, [&](int k) {
      if (k % 2 == 0 && spawned < 200) {
        SphereCollider ball;
        ball.center = Vec3(u(rng), u(rng), 2.0);
        ball.radius = 0.015;
        ball.mass = 0.05;
        ball.velocity = Vec3(0, 0, -3.0);
        sim.addSphere(ball);
        ++spawned;
      }
      std::vector<int> gone;
      for (const SphereCollider& s : sim.colliders().spheres()) {
        if (s.center.z() < -1.0 || k >= 480) gone.push_back(s.id);
      }
      for (int id : gone) sim.removeSphere(id);
    });
    std::printf(
        "200 balls, self-collision %s: final max strain %.3f (left alone: %.3f), "
        "intersecting pairs max %d, at the end %d, failed steps %d\n",
        self ? "on" : "off", r.final_strain, base.final_strain, r.max_intersections,
        r.final_intersections, r.failed_steps);
    if (!self) continue;
    EXPECT_EQ(r.max_intersections, 0);
    EXPECT_EQ(r.failed_steps, 0);
    EXPECT_LT(r.final_strain, 1.2 * base.final_strain + 0.02);
  }
}

}  // namespace
}  // namespace cloth_sim
