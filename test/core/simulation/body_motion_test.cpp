// Bodies moving with the simulation (Simulation::addBody, setBodyPoseSource): a box pushed into
// a hanging cloth leaves no particle inside it, a thin plate sweeps a cloth ahead of itself at
// any speed tried, and two box fingers lift a cloth off a table by friction alone at mu = 1
// and let it slip out at mu = 0.1.
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <string>

#include <gtest/gtest.h>

#include "cloth_sim/core/io/scene.h"
#include "test_util.h"

namespace cloth_sim {
namespace {

using Iso = Eigen::Isometry3d;

Iso at(double x, double y, double z) { return Iso(Eigen::Translation3d(x, y, z)); }

BodyCollider box(const Vec3& size, double margin, double friction) {
  BodyCollider b;
  b.geometry.shape = BodyShape::kBox;
  b.geometry.size = size;
  b.margin = margin;
  b.friction = friction;
  b.follows_frame = true;
  return b;
}

/// How far (m) the particle farthest inside body @p b's shape (not its margin) is; <= 0: none.
double deepest(const Simulation& sim, const BodyCollider& b) {
  double depth = -INFINITY;
  const Points& x = sim.state().positions;
  for (Eigen::Index i = 0; i < x.cols(); ++i) {
    depth = std::max(depth, -b.geometry.distance(b.pose().inverse() * Vec3(x.col(i))));
  }
  return depth;
}

/// A 0.4 m sheet, 10 x 10, hanging in the x-z plane from its pinned top row at z = 1.2.
Simulation hangingSheet(double gravity = -9.81, bool pinned = true) {
  return makeSimulation(parseScene(
      "solver: {substeps: 8, iterations: 4}\ngravity: [0, 0, " + std::to_string(gravity) + "]\n" +
          R"(cloth: {grid: {rows: 10, cols: 10, size: [0.4, 0.4], position: [0, 0, 1], orientation_rpy: [1.5707963267948966, 0, 0]}}
material: {areal_density: 0.2, damping: 1, springs: {structural: 400, shear: 40, bending: 4}}
)" + (pinned ? "pins: [{edge: top}]\n" : ""),
      "sheet"));
}

TEST(BodyMotion, ABoxPushedIntoAHangingClothLeavesNoParticleInside) {
  Simulation sim = hangingSheet();
  const double speed = 1.0;  // m/s along +y, through the sheet's plane y = 0
  const int id = sim.addBody(box(Vec3(0.12, 0.12, 0.12), 0.005, 0.0));
  sim.setBodyPoseSource([&](int, double t) { return at(0.0, -0.2 + speed * t, 0.95); });
  double worst = -INFINITY, pushed = -INFINITY;
  for (int frame = 0; frame < 30; ++frame) {  // 0.5 s: 0.3 m, 0.24 m past the sheet
    ASSERT_EQ(sim.step().status, StepStatus::kOk) << frame;
    worst = std::max(worst, deepest(sim, *sim.colliders().bodies().find(id)));
  }
  pushed = sim.state().positions.row(1).maxCoeff();
  RecordProperty("deepest_particle_m", std::to_string(worst));
  RecordProperty("cloth_pushed_to_y_m", std::to_string(pushed));
  EXPECT_LT(worst, -0.005 + 1e-9);  // every particle at least the margin outside
  EXPECT_GT(pushed, 0.3 - 0.2 - 0.06);  // the cloth went with the box's front face (y = 0.04)
}

TEST(BodyMotion, AThinPlateSweepsAFreeClothAheadAtAnySpeedTried) {
  // A 1 cm plate wider than the sheet crosses it at up to 100 m/s (0.2 m, 20 plate thicknesses,
  // per substep): no particle is ever inside, and every one ends ahead of its front face.
  for (double speed : {1.0, 10.0, 30.0, 100.0}) {
    Simulation sim = hangingSheet(0.0, false);
    const int id = sim.addBody(box(Vec3(0.6, 0.01, 0.6), 0.005, 0.0));
    const double start = -0.1;
    sim.setBodyPose(id, at(0.0, start, 1.0));  // there at t = 0
    sim.setBodyPoseSource([&](int, double t) { return at(0.0, start + speed * t, 1.0); });
    const int frames = static_cast<int>(std::ceil((0.3 - start) / speed * 60.0));
    double worst = -INFINITY;
    for (int frame = 0; frame < frames; ++frame) {
      ASSERT_EQ(sim.step().status, StepStatus::kOk) << speed << " m/s, frame " << frame;
      worst = std::max(worst, deepest(sim, *sim.colliders().bodies().find(id)));
    }
    const double front = sim.colliders().bodies().find(id)->pose().translation().y() + 0.005;
    const double behind = front - sim.state().positions.row(1).minCoeff();
    std::printf("plate at %g m/s: deepest particle %.3g m, farthest behind the front %.3g m\n",
                speed, worst, behind);
    EXPECT_LT(worst, 0.0) << speed;
    EXPECT_LT(behind, 1e-6) << speed;
  }
}

/// The shipped pinch scene with two box fingers (friction @p mu) on a scripted gripper: the lower
/// jaw flush with the table top under the overhanging edge (x = 0.33), the upper one closed
/// onto it to a 9 mm gap by t = 1.5 s (5 mm margins: 1 mm of squeeze), both lifted by 0.5 m
/// from t = 2 s to 4 s, held to 5 s. Returns
/// the rise of the cloth's centre of mass and of the fingers over the last 0.8 s of the lift
/// (@p com_rise, @p finger_rise) and the final height of the centre of mass above the table.
struct PinchResult {
  double com_rise, finger_rise, final_height;
};

double smooth(double s) {
  s = std::clamp(s, 0.0, 1.0);
  return s * s * (3.0 - 2.0 * s);
}

/// Height (m) of the fingers' gap centre above the table top at time @p t (s).
double liftAt(double t) { return 0.5 * smooth((t - 2.0) / 2.0); }

PinchResult pinch(double mu) {
  Simulation sim = makeSimulation(loadSceneFile(test::sourcePath("config/scenes/pinch.yaml")));
  const double top = 0.75, x = 0.33, gap = 0.009, thick = 0.02;
  const int upper = sim.addBody(box(Vec3(0.04, 0.16, thick), 0.005, mu));
  const int lower = sim.addBody(box(Vec3(0.04, 0.16, thick), 0.005, mu));
  // The lower jaw lies flush with the table top under the overhang; the upper one comes down
  // from 8 cm above it to the gap.
  const auto pose = [&](int id, double t) {
    const double open = 0.08 * (1.0 - smooth((t - 0.5) / 1.0));
    const double face = top + liftAt(t);  // the lower jaw's upper face
    return id == upper ? at(x, 0.0, face + gap + open + 0.5 * thick) : at(x, 0.0, face - 0.5 * thick);
  };
  sim.setBodyPose(upper, pose(upper, 0.0));
  sim.setBodyPose(lower, pose(lower, 0.0));
  sim.setBodyPoseSource(pose);
  const auto com = [&] { return sim.state().positions.row(2).mean(); };
  double com_start = 0.0;
  for (int frame = 1; frame <= 300; ++frame) {
    EXPECT_EQ(sim.step().status, StepStatus::kOk) << frame;
    if (frame == 192) com_start = com();  // t = 3.2 s: the cloth hangs free of the table
  }
  return {com() - com_start, liftAt(5.0) - liftAt(3.2), com() - top};
}

TEST(BodyMotion, TwoFingersLiftAClothByFrictionAtMu1AndLetItSlipAtMu01) {
  const PinchResult held = pinch(1.0), slipped = pinch(0.1);
  std::printf("pinch mu = 1: centre of mass rose %.4f m while the fingers rose %.4f m; "
              "it hangs %.3f m above the table\n",
              held.com_rise, held.finger_rise, held.final_height);
  std::printf("pinch mu = 0.1: centre of mass rose %.4f m; it ends %.3f m above the table\n",
              slipped.com_rise, slipped.final_height);
  EXPECT_NEAR(held.com_rise, held.finger_rise, 0.01);
  EXPECT_GT(held.final_height, 0.2);  // hanging 0.2 m below fingers 0.5 m up
  EXPECT_LT(slipped.final_height, 0.05);  // not carried: back on the table, or off it to the floor
}

}  // namespace
}  // namespace cloth_sim
