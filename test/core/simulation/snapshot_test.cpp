// Snapshots (Simulation::snapshot, restore, setState): a restored snapshot continues exactly as
// the run it was taken from, bit for bit, on scenes with every kind of carried-over state:
// contacts solved in the step (sphere, ground, dynamic balls: warm-started forces), mesh
// obstacles, bodies on moving frames, grasps, BDF2's history, the solver's warm start,
// self-contact, a pin move and a sphere move still pending. A member added to Simulation and
// not to SimulationSnapshot makes one of these differ.
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cloth_sim/core/io/scene.h"
#include "test_util.h"

namespace cloth_sim {
namespace {

using Iso = Eigen::Isometry3d;

/// Whether @p a and @p b hold the same bits.
bool sameBits(const Points& a, const Points& b) {
  return a.cols() == b.cols() &&
         std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<std::size_t>(a.size())) == 0;
}

struct Frames {
  std::vector<Points> x, v;
  std::vector<double> t;
};

Frames run(Simulation& sim, int frames) {
  Frames out;
  for (int k = 0; k < frames; ++k) {
    sim.step();
    out.x.push_back(sim.state().positions);
    out.v.push_back(sim.state().velocities);
    out.t.push_back(sim.state().time);
  }
  return out;
}

void expectSame(const Frames& a, const Frames& b, const std::string& what) {
  ASSERT_EQ(a.x.size(), b.x.size());
  for (std::size_t k = 0; k < a.x.size(); ++k) {
    ASSERT_TRUE(sameBits(a.x[k], b.x[k])) << what << ": positions differ at frame " << k;
    ASSERT_TRUE(sameBits(a.v[k], b.v[k])) << what << ": velocities differ at frame " << k;
    ASSERT_EQ(a.t[k], b.t[k]) << what;
  }
}

/// Pose sources that depend on the time only, as a script publishing ahead would give.
void drive(Simulation& sim) {
  sim.setGraspPoseSource([](int, double t) {
    return Iso(Eigen::Translation3d(0.1 * std::sin(3 * t), 0.0, 0.2 * t) *
               Eigen::AngleAxisd(0.5 * t, Vec3::UnitZ()));
  });
  sim.setBodyPoseSource([](int, double t) { return Iso(Eigen::Translation3d(0.0, -0.3 + 0.4 * t, 0.9)); });
}

/// Runs @p warmup frames of @p scene (with @p edit before the snapshot), snapshots, runs
/// @p frames, then restores the snapshot into the same simulation and into a fresh one made
/// from the scene, and checks that both continue bit for bit.
void checkContinuation(const SceneConfig& scene, int warmup, int frames,
                       const std::function<void(Simulation&)>& edit) {
  Simulation sim = makeSimulation(scene);
  drive(sim);
  for (int k = 0; k < warmup; ++k) sim.step();
  if (edit) edit(sim);
  const SimulationSnapshot snap = sim.snapshot();
  const Frames original = run(sim, frames);
  sim.restore(snap);
  expectSame(original, run(sim, frames), scene.name + " restored in place");
  Simulation other = makeSimulation(scene);
  drive(other);
  other.restore(snap);
  expectSame(original, run(other, frames), scene.name + " restored into a new simulation");
}

SceneConfig shipped(const std::string& name) {
  return loadSceneFile(test::sourcePath("config/scenes/" + name + ".yaml"));
}

/// @p scene with @p solver, the warm start on and @p integrator.
SceneConfig with(SceneConfig scene, const std::string& solver, const std::string& integrator) {
  scene.options.solver = solver;
  scene.options.settings.warm_start = solver != "newton";
  scene.options.settings.integrator = integratorFromName(integrator);
  return scene;
}

TEST(Snapshot, DrapeContinuesBitForBit) {  // sphere and ground, contacts in the solve, BDF2
  checkContinuation(with(shipped("drape"), "chebyshev", "bdf2"), 40, 15, nullptr);
}

TEST(Snapshot, GravityWellContinuesBitForBit) {  // dynamic balls: velocities, spins, forces
  checkContinuation(with(shipped("gravity_well"), "anderson", "bdf2"), 20, 10, nullptr);
}

TEST(Snapshot, TableclothContinuesBitForBit) {  // mesh cloth on a mesh obstacle
  checkContinuation(with(shipped("tablecloth"), "local_global", "implicit_euler"), 30, 10, nullptr);
}

TEST(Snapshot, GraspBodyAndPendingMovesContinueBitForBit) {
  // A grasped corner on a moving, turning frame, a box on a frame sweeping through, a pin move
  // and a sphere move made just before the snapshot (still to be spread over the next frame),
  // self-contact on, and a stiffness changed at run time.
  SceneConfig scene = with(shipped("hanging"), "local_global", "bdf2");
  scene.options.self_contact.enabled = true;
  BodyCollider box;
  box.geometry.size = Vec3(0.1, 0.1, 0.1);
  box.follows_frame = true;
  box.friction = 0.5;
  scene.bodies.push_back(box);
  checkContinuation(scene, 20, 15, [](Simulation& sim) {
    sim.addGrasp({static_cast<int>(sim.model().particleCount()) - 1}, Iso::Identity());
    sim.movePin(sim.pins().pins().front().id, Vec3(-0.3, 0.2, 1.6));
    const int s = sim.addSphere(SphereCollider{-1, Vec3(0.0, -0.5, 0.8), 0.1});
    sim.step();
    sim.moveSphere(s, Vec3(0.0, -0.4, 0.8), Vec3(0.0, 0.5, 0.0));
    sim.setFamilyStiffness(SpringFamily::kStructural, 123.0);
  });
}

TEST(Snapshot, ASnapshotRightAfterARestartContinuesBitForBit) {
  // A pin added just before the snapshot: BDF2 restarts with an implicit Euler step (another
  // h_i, another factor), so the warm start carried must not be used for it.
  checkContinuation(with(shipped("drape"), "local_global", "bdf2"), 30, 10,
                    [](Simulation& sim) { sim.addPinHere(0); });
}

TEST(Snapshot, NewtonContinuesBitForBit) {
  checkContinuation(with(shipped("trampoline"), "newton", "implicit_euler"), 10, 5, nullptr);
}

TEST(Snapshot, RestoreRefusesAnotherClothAndSetStateChecksItsInput) {
  Simulation hanging = makeSimulation(shipped("hanging"));
  Simulation drape = makeSimulation(shipped("drape"));
  const State before = hanging.state();
  EXPECT_THROW(hanging.restore(drape.snapshot()), std::invalid_argument);
  EXPECT_TRUE(sameBits(hanging.state().positions, before.positions));
  const int n = hanging.model().particleCount();
  Points x = hanging.state().positions, v = Points::Zero(3, n);
  x.col(3) += Vec3(0, 0, 0.01);
  for (const auto& [bad_x, bad_t, field] :
       std::vector<std::tuple<Points, double, std::string>>{{Points::Zero(3, n - 1), 0.0, "positions: "},
                                                            {x, -1.0, "time -1"}}) {
    try {
      hanging.setState(bad_x, v, bad_t);
      ADD_FAILURE() << field;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  }
  Points nan_v = v;
  nan_v(0, 0) = NAN;
  EXPECT_THROW(hanging.setState(x, nan_v, 0.0), std::invalid_argument);
  EXPECT_TRUE(sameBits(hanging.state().positions, before.positions));
  hanging.setState(x, v, 2.5);
  EXPECT_TRUE(sameBits(hanging.state().positions, x));
  EXPECT_EQ(hanging.state().time, 2.5);
  EXPECT_FALSE(hanging.state().has_previous);
}

}  // namespace
}  // namespace cloth_sim
