// Self-contact in whole scenes (docs/testing.md, "Self-contact"): the shipped fold and pile
// scenes, a randomized set of folds and drops (fixed, printed seeds), and the option off giving
// bit-identical trajectories. Every step must leave no intersecting pair of non-adjacent
// triangles (IntersectionCounter), and at rest no particle may be closer than t/2 to a triangle
// of another layer (a triangle whose vertices are all more than 2 t away from it on the cloth
// at rest, so that the bend of a fold does not count as two layers).
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
/// @p to, raised by @p thickness (on top of the other layer), in @p duration s.
Vec3 foldTarget(const Vec3& from, const Vec3& to, double lift, double thickness, double duration,
                double time) {
  const double s = std::min(1.0, time / duration);
  const double along = 0.5 * (1.0 - std::cos(M_PI * s));
  return from + along * (to - from) + Vec3(0, 0, lift * std::sin(M_PI * s) + thickness * along);
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
  std::printf("%s: %d steps, max intersecting pairs %d, failed steps %d, min layer distance "
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
  // It did fold: the corner lies on the opposite corner, one layer up.
  const Vec3 c = sim.state().positions.col(corner), o = sim.state().positions.col(opposite);
  EXPECT_LT((c - o).head<2>().norm(), 0.15);
  EXPECT_GT(c.z() - o.z(), 0.5 * r.thickness);
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
  Simulation off = makeSimulation(parseScene(text + "\nself_collision: {enabled: false, thickness: 0.01}\n", path));
  for (int k = 0; k < 40; ++k) {
    const StepReport a = absent.step(), b = off.step();
    EXPECT_EQ(a.intersections, -1);
    EXPECT_EQ(b.intersections, -1);
  }
  EXPECT_TRUE(absent.state().positions == off.state().positions) << scene;
  EXPECT_TRUE(absent.state().velocities == off.state().velocities) << scene;
}

TEST(SelfContactScenes, OptionOffGivesBitIdenticalTrajectories) {
  for (const char* scene : {"hanging", "drape", "gravity_well", "tablecloth"}) {
    SCOPED_TRACE(scene);
    expectOffIsAbsent(scene);
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
  y << "self_collision: {thickness: " << thickness << ", friction: " << 0.5 * u(rng) << "}\n";
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

}  // namespace
}  // namespace cloth_sim
