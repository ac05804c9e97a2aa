// Two-way coupling between cloth and dynamic (massive) spheres, through Simulation.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "cloth_sim/core/collision/contact_projection.h"
#include "cloth_sim/core/solvers/implicit_euler_problem.h"
#include "cloth_sim/core/solvers/newton_solver.h"
#include "test_util.h"

namespace cloth_sim {
namespace {

/// A horizontal sheet at z = 0, rows x cols, @p size m wide, pinned on all four edges.
Simulation pinnedSheet(int n, double size, double k, const std::string& solver,
                       const SolverSettings& settings, double damping) {
  GridSpec spec;
  spec.rows = spec.cols = n;
  spec.width = spec.height = size;
  spec.material.areal_density = 0.2;
  spec.material.structural = k;
  spec.material.shear = 0.1 * k;
  BuiltObject g = buildGrid(spec);
  g.model.damping = damping;
  PinSet pins;
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c)
      if (r == 0 || c == 0 || r == n - 1 || c == n - 1) {
        const int v = gridVertex(r, c, n);
        pins.add(v, g.rest_positions.col(v), 0.0, n * n);
      }
  SimulationOptions options;
  options.solver = solver;
  options.settings = settings;
  return Simulation(g.model, g.rest_positions, pins, Colliders(), options);
}

SphereCollider heavyBall(double mass, double radius, const Vec3& center, const Vec3& velocity) {
  SphereCollider s;
  s.center = center;
  s.radius = radius;
  s.velocity = velocity;
  s.mass = mass;
  return s;
}

TEST(DynamicSpheres, SphereHittingAFreeClothConservesTotalMomentum) {
  // No gravity, no pins, no damping: the cloth solver and the contact response exchange
  // momentum between cloth and sphere and conserve the total.
  BuiltObject g = test::makeGrid(9, 9, 200.0, 20.0, 0.0);
  g.model.gravity.setZero();
  Simulation sim(g.model, g.rest_positions, PinSet(), Colliders(), SimulationOptions());
  sim.addSphere(heavyBall(0.05, 0.1, Vec3(0.05, 0.02, 1.5), Vec3(0.3, 0.0, -3.0)));
  auto total = [&] {
    return Vec3(sim.state().velocities * sim.model().mass + 0.05 * sim.colliders().spheres()[0].velocity);
  };
  const Vec3 p0 = total();
  for (int k = 0; k < 90; ++k) ASSERT_EQ(sim.step().status, StepStatus::kOk);
  EXPECT_LT((total() - p0).norm(), 1e-9 * p0.norm());
  // Momentum really moved: the cloth (0.1 kg) now carries a good part of it downwards.
  EXPECT_LT((sim.state().velocities * sim.model().mass).z(), 0.3 * p0.z());
}

TEST(DynamicSpheres, SphereHittingAFreeClothConservesTotalMomentumUnderBdf2) {
  // The same exchange under BDF2. Its momentum recurrence, P_{n+1} = (4 P_n - P_{n-1}) / 3 +
  // (2h/3) F, conserves Q = (3 P_n - P_{n-1}) / 2, which gains h F per step; the ball, stepped
  // over h, gains h F_ball. So Q_cloth + P_ball is conserved at every step, and once the ball
  // has left the cloth P_cloth tends to Q_cloth. With the contact force scaled by h^2 in the
  // cloth's right-hand side instead of h_i^2 = (2h/3)^2, the cloth took 9/4 of the ball's loss.
  BuiltObject g = test::makeGrid(9, 9, 200.0, 20.0, 0.0);
  g.model.gravity.setZero();
  SimulationOptions options;
  options.settings.integrator = Integrator::kBdf2;
  options.settings.max_iterations = 10;
  Simulation sim(g.model, g.rest_positions, PinSet(), Colliders(), options);
  const double ball_mass = 0.05;
  sim.addSphere(heavyBall(ball_mass, 0.1, Vec3(0.05, 0.02, 1.5), Vec3(0.3, 0.0, -3.0)));
  const Eigen::VectorXd& mass = sim.model().mass;
  auto ball = [&] { return Vec3(ball_mass * sim.colliders().spheres()[0].velocity); };
  auto conserved = [&] {
    const State& s = sim.state();
    const Vec3 p = s.velocities * mass;
    const Vec3 q = s.has_previous ? Vec3(1.5 * p - 0.5 * (s.previous_velocities * mass)) : p;
    return Vec3(q + ball());
  };
  const Vec3 p0 = conserved();
  double cloth_took = 0.0;
  for (int k = 0; k < 90; ++k) {
    ASSERT_EQ(sim.step().status, StepStatus::kOk);
    ASSERT_LT((conserved() - p0).norm(), 1e-9 * p0.norm()) << "step " << k;
    cloth_took = std::max(cloth_took, -(sim.state().velocities * mass).z());
  }
  // Momentum really moved (the same bar as under implicit Euler), and it is all accounted for
  // by the instantaneous momenta too once the exchange is over.
  EXPECT_LT((sim.state().velocities * mass).z(), 0.3 * p0.z());
  EXPECT_LT((Vec3(sim.state().velocities * mass) + ball() - p0).norm(), 1e-6 * p0.norm());
  std::printf("bdf2: the cloth took %.4f of %.4f kg m/s\n", cloth_took, -p0.z());
}

TEST(DynamicSpheres, ThrownSphereBouncesBackFromAPinnedSheet) {
  // Thrown down at 4 m/s onto a sheet pinned on its edges: the sheet stretches, stops it and
  // throws it back up. Implicit Euler damps the sheet, so the rebound is a fraction of 4 m/s.
  Simulation sim = pinnedSheet(21, 1.0, 300.0, "local_global", SolverSettings{}, 0.0);
  sim.addSphere(heavyBall(0.1, 0.08, Vec3(0.0, 0.0, 0.5), Vec3(0.0, 0.0, -4.0)));
  double lowest = 1.0, rebound_speed = 0.0, rebound_height = -1.0;
  for (int k = 0; k < 90; ++k) {
    ASSERT_EQ(sim.step().status, StepStatus::kOk);
    const SphereCollider& s = sim.colliders().spheres()[0];
    if (s.center.z() < lowest) {
      lowest = s.center.z();
      rebound_speed = 0.0;
      rebound_height = lowest;
    }
    rebound_speed = std::max(rebound_speed, s.velocity.z());
    rebound_height = std::max(rebound_height, s.center.z());
  }
  EXPECT_LT(lowest, -0.03);                   // it pushed the sheet down
  EXPECT_GT(rebound_speed, 0.4);              // the sheet threw it back up (10 % of 4 m/s)...
  EXPECT_GT(rebound_height - lowest, 0.04);   // ...and it rose above the bottom of the well
}

TEST(DynamicSpheres, ABallKeepsFallingAfterASwitchToASolverWithoutContactForces) {
  // Newton does not solve contact forces: after a switch from local/global, the ball must fall
  // freely, not be put back where local/global's last step left it.
  Simulation sim = pinnedSheet(9, 1.0, 300.0, "local_global", SolverSettings{}, 0.0);
  sim.addSphere(heavyBall(0.1, 0.05, Vec3(0.0, 0.0, 2.0), Vec3::Zero()));
  for (int k = 0; k < 5; ++k) ASSERT_EQ(sim.step().status, StepStatus::kOk);
  sim.setSolver("newton");
  const double z0 = sim.colliders().spheres()[0].center.z();
  const double v0 = sim.colliders().spheres()[0].velocity.z();
  const int steps = 10;
  for (int k = 0; k < steps; ++k) ASSERT_EQ(sim.step().status, StepStatus::kOk);
  const double h = sim.substepTime();
  // Semi-implicit Euler free fall (no drag: damping 0), far above the sheet.
  const double v = v0 - 9.81 * h * steps;
  double z = z0;
  for (int k = 1; k <= steps; ++k) z += h * (v0 - 9.81 * h * k);
  EXPECT_NEAR(sim.colliders().spheres()[0].velocity.z(), v, 1e-9);
  EXPECT_NEAR(sim.colliders().spheres()[0].center.z(), z, 1e-9);
}

TEST(DynamicSpheres, ABallRestingOnTheSheetIsCountedAsInContactEveryFrame) {
  // Held by contact forces in the solve, the resting ball needs no projection: the report's
  // contacts must still show it (they count the forces that pushed, not only projections).
  SolverSettings settings;
  settings.substeps = 4;
  settings.max_iterations = 2;
  Simulation sim = pinnedSheet(15, 1.0, 300.0, "local_global", settings, 1.0);
  sim.addSphere(heavyBall(0.1, 0.1, Vec3(0.0, 0.0, 0.12), Vec3::Zero()));
  int frames_in_contact = 0;
  for (int k = 0; k < 120; ++k) {
    const StepReport report = sim.step();
    ASSERT_EQ(report.status, StepStatus::kOk);
    if (k >= 60) {  // settled on the sheet
      EXPECT_GT(report.contacts, 0) << "frame " << k;
      frames_in_contact += report.contacts > 0 ? 1 : 0;
    }
  }
  EXPECT_EQ(frames_in_contact, 60);
  EXPECT_GT(sim.colliders().spheres()[0].center.z(), -0.3);  // held, not fallen through
}

TEST(DynamicSpheres, FastSphereDoesNotTunnelThroughTheSheet) {
  // 20 m/s: 33 cm per step at 60 Hz, more than the ball's diameter. Contacts are found along
  // the ball's path relative to the cloth (continuous detection, in the solve and after it);
  // the sheet must catch the ball (3 cloth spacings in radius) and keep it above itself.
  Simulation sim = pinnedSheet(31, 1.0, 1000.0, "local_global", SolverSettings{}, 0.0);
  sim.addSphere(heavyBall(0.05, 0.1, Vec3(0.01, 0.013, 0.5), Vec3(0.0, 0.0, -20.0)));
  double slowest = -20.0;
  for (int k = 0; k < 60; ++k) {
    ASSERT_EQ(sim.step().status, StepStatus::kOk);
    const SphereCollider& s = sim.colliders().spheres()[0];
    // The cloth under the ball (the particles near its x, y) is below its centre.
    const Points& x = sim.state().positions;
    Eigen::Index nearest = 0;
    (x.topRows(2).colwise() - s.center.head<2>()).colwise().squaredNorm().minCoeff(&nearest);
    ASSERT_LT(x(2, nearest), s.center.z()) << "step " << k;
    // Stated tolerance: contact solved with the step leaves at most 5 % of the radius overlap.
    ASSERT_GE((x.colwise() - s.center).colwise().norm().minCoeff(), 0.95 * s.radius - 1e-9);
    slowest = std::max(slowest, s.velocity.z());
  }
  EXPECT_GT(slowest, 0.0);  // caught and thrown back up
}

TEST(DynamicSpheres, FrictionMakesABallRollOnTheSheet) {
  // A ball sent sliding over a sheet: with friction the cloth spins it up until it rolls
  // (w r = v, to 10 %); without, it keeps sliding with no spin.
  for (const double mu : {0.5, 0.0}) {
    Simulation sim = pinnedSheet(41, 2.0, 400.0, "local_global", SolverSettings{}, 0.2);
    SphereCollider ball = heavyBall(0.2, 0.1, Vec3(-0.5, 0.0, 0.1), Vec3(1.0, 0.0, 0.0));
    ball.friction = mu;
    sim.addSphere(ball);
    for (int k = 0; k < 30; ++k) ASSERT_EQ(sim.step().status, StepStatus::kOk);
    const SphereCollider& s = sim.colliders().spheres()[0];
    const double rolling = s.angular_velocity.y() * s.radius;
    if (mu > 0.0) EXPECT_NEAR(rolling, s.velocity.x(), 0.1 * s.velocity.x());
    else EXPECT_LT(std::abs(rolling), 0.05 * s.velocity.x());
    EXPECT_GT(s.velocity.x(), 0.2);
  }
}

/// Settled sink depth (m below the pinned edges) of the lowest sheet particle under a ball of
/// @p mass resting in the middle of a sheet.
struct Settled {
  Simulation sim;
  double depth;
};

Settled settle(double mass) {
  Simulation sim = pinnedSheet(13, 1.0, 100.0, "local_global", test::convergedSettings(500, 1e-9), 8.0);
  sim.addSphere(heavyBall(mass, 0.1, Vec3(0.0, 0.0, 0.1), Vec3::Zero()));
  for (int k = 0; k < 300; ++k) EXPECT_EQ(sim.step().status, StepStatus::kOk);
  const double depth = -sim.state().positions.row(2).minCoeff();
  return Settled{std::move(sim), depth};
}

TEST(DynamicSpheres, SinkDepthGrowsWithMassAndMatchesNewtonsStaticEquilibrium) {
  double previous = 0.0;
  for (double mass : {0.05, 0.2, 0.8}) {
    Settled s = settle(mass);
    EXPECT_GT(s.depth, previous + 0.01) << "mass " << mass;  // monotone, clearly
    std::printf("[ measured ] mass %.2f kg: sink depth %.4f m\n", mass, s.depth);
    previous = s.depth;
  }
  // Static check for the heaviest: hold the cloth triangles touching the ball where they are
  // and let Newton find the equilibrium of all the other particles (implicit Euler with
  // h = 100 s is a static solve). They must already be there, and what the held particles
  // press on the ball with must carry its weight.
  Settled s = settle(0.8);
  const SphereCollider ball = s.sim.colliders().spheres()[0];
  EXPECT_LT(ball.velocity.norm(), 1e-6);
  Model model = s.sim.model();
  model.damping = 0.0;
  PinSet pins = s.sim.pins();
  const Points& x = s.sim.state().positions;
  std::vector<int> touching;
  for (int t = 0; t < model.triangles.cols(); ++t) {
    const Vec3 a = x.col(model.triangles(0, t)), b = x.col(model.triangles(1, t)),
               c = x.col(model.triangles(2, t));
    if ((closestPointOnTriangle(ball.center, a, b, c) - ball.center).norm() > ball.radius + 1e-4) continue;
    for (int k = 0; k < 3; ++k) {
      const int v = model.triangles(k, t);
      if (pins.findByVertex(v) == nullptr) {
        touching.push_back(v);
        pins.add(v, x.col(v), 0.0, model.particleCount());
      }
    }
  }
  ASSERT_GE(touching.size(), 3u);
  State still = State::atRest(x);
  NewtonSolver newton;
  newton.step({model, pins, 100.0, 1}, test::convergedSettings(100, 1e-12), still);
  Points forces;
  totalForces(model, pins, still.positions, forces);
  // Newton did reach the static equilibrium: no net force left on any free particle.
  double residual = 0.0;
  for (int i = 0; i < model.particleCount(); ++i) {
    if (pins.findByVertex(i) == nullptr) residual = std::max(residual, forces.col(i).norm());
  }
  EXPECT_LT(residual, 1e-9);
  // Stated tolerance: the simulated sheet is within 0.1 mm of that equilibrium.
  EXPECT_LT((still.positions - x).cwiseAbs().maxCoeff(), 1e-4);
  Vec3 on_ball = Vec3::Zero();
  for (int i : touching) on_ball += forces.col(i);  // springs + weight the ball must balance
  EXPECT_NEAR(on_ball.z(), 0.8 * 9.81, 0.01 * 0.8 * 9.81);  // within 1 % of its weight
  std::printf("[ measured ] sheet vs Newton static: %.3g m; lift %.5f N for a weight of %.5f N\n",
              (still.positions - x).cwiseAbs().maxCoeff(), on_ball.z(), 0.8 * 9.81);
  EXPECT_LT(on_ball.head<2>().norm(), 0.01 * 0.8 * 9.81);
}

}  // namespace
}  // namespace cloth_sim
