#include <random>

#include <gtest/gtest.h>

#include "cloth_sim/core/model/grid_builder.h"
#include "cloth_sim/core/collision/mesh_obstacle.h"
#include "cloth_sim/core/io/scene.h"
#include "test_util.h"

namespace cloth_sim {
namespace {

/// A flat square floor of (n-1)^2 * 2 triangles spanning [-1, 1]^2 at z = 0.
TriangleMesh floorMesh(int n) {
  GridSpec spec;
  spec.rows = spec.cols = n;
  spec.width = spec.height = 2.0;
  const BuiltObject g = buildGrid(spec);
  return TriangleMesh{g.rest_positions, g.model.triangles};
}

TEST(MeshObstacle, FallingParticleStopsAtThicknessAndKeepsItsSlide) {
  const MeshObstacle floor(floorMesh(5), 0.01, 0.0);
  Vec3 end(0.31, 0.2, -0.03);
  EXPECT_TRUE(floor.collide(Vec3(0.3, 0.2, 0.02), end));
  EXPECT_NEAR(end.z(), 0.01, 1e-12);
  EXPECT_NEAR(end.x(), 0.31, 1e-12);
  Vec3 above(0.3, 0.2, 0.5);
  EXPECT_FALSE(floor.collide(Vec3(0.3, 0.2, 0.6), above));  // far away: untouched
}

TEST(MeshObstacle, FastParticleDoesNotTunnelAndEachSideIsKept) {
  const MeshObstacle floor(floorMesh(5), 0.01, 0.0);
  Vec3 from_above(0.1, 0.1, -0.5);
  floor.collide(Vec3(0.1, 0.1, 0.5), from_above);  // 1 m in one step, straight through
  EXPECT_NEAR(from_above.z(), 0.01, 1e-12);
  Vec3 from_below(0.1, 0.1, 0.5);
  floor.collide(Vec3(0.1, 0.1, -0.5), from_below);  // an open surface: it stays below
  EXPECT_NEAR(from_below.z(), -0.01, 1e-12);
}

TEST(MeshObstacle, EdgesAndCornersPushOutwardAndFrictionSticks) {
  const MeshObstacle floor(floorMesh(3), 0.05, 0.0);
  Vec3 beside(1.02, 0.0, 0.01);  // just outside the border, inside the thickness shell
  floor.collide(Vec3(1.02, 0.0, 0.2), beside);
  EXPECT_NEAR(floor.distance(beside), 0.05, 1e-9);
  const MeshObstacle sticky(floorMesh(3), 0.01, 1.0);
  Vec3 end(0.02, 0.0, -0.05);  // slide 2 cm < mu * 6 cm correction: sticks
  sticky.collide(Vec3(0.0, 0.0, 0.01), end);
  EXPECT_NEAR(end.x(), 0.0, 1e-12);
  EXPECT_NEAR(end.z(), 0.01, 1e-12);
}

TEST(MeshObstacle, HashGridGivesTheBruteForceAnswerWithFewCandidates) {
  const TriangleMesh mesh = floorMesh(101);  // 20,000 triangles
  const MeshObstacle hashed(mesh, 0.01, 0.2);
  const MeshObstacle brute(mesh, 0.01, 0.2, /*cell_size=*/100.0);  // one cell: every triangle
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.2, 1.2), z(-0.05, 0.05);
  int most = 0;
  for (int k = 0; k < 500; ++k) {
    const Vec3 start(u(rng), u(rng), 0.05 + std::abs(z(rng)));
    Vec3 a(start + Vec3(0.03 * z(rng), 0.03 * z(rng), -0.1 * std::abs(z(rng)) - 0.02)), b = a;
    hashed.collide(start, a);
    most = std::max(most, hashed.lastCandidates());
    brute.collide(start, b);
    ASSERT_NEAR((a - b).norm(), 0.0, 1e-12) << k;
  }
  EXPECT_LT(most, 100);  // of 20,000: the cost per particle does not grow with the mesh
}

TEST(MeshObstacle, TableclothNeverEntersTheTable) {
  Simulation sim = makeSimulation(loadSceneFile(test::sourcePath("config/scenes/tablecloth.yaml")));
  ASSERT_EQ(sim.colliders().meshes().size(), 1u);
  const MeshObstacle& table = *sim.colliders().meshes()[0];
  for (int k = 0; k < 120; ++k) {
    ASSERT_EQ(sim.step().status, StepStatus::kOk);
    if (k % 10 != 9) continue;
    for (int i = 0; i < sim.model().particleCount(); ++i) {
      ASSERT_GE(table.distance(sim.state().positions.col(i)), 0.01 - 1e-9) << "step " << k;
    }
  }
  // It came to lie on the table: its centre is just above the top face.
  EXPECT_NEAR(sim.state().positions(2, 0), 0.76, 0.01);
}

}  // namespace
}  // namespace cloth_sim
