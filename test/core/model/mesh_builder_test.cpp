#include <set>
#include <tuple>

#include <gtest/gtest.h>

#include "cloth_sim/core/solvers/implicit_euler_problem.h"
#include "cloth_sim/core/model/mesh_builder.h"
#include "cloth_sim/core/simulation/simulation.h"
#include "test_util.h"

namespace cloth_sim {
namespace {

MeshSpec specFor(const TriangleMesh& mesh) {
  MeshSpec spec;
  spec.mesh = mesh;
  spec.source = "test";
  spec.material.areal_density = 0.3;
  spec.material.structural = 200.0;
  spec.material.has_bending = true;
  spec.material.bending = 5.0;
  return spec;
}

TEST(MeshBuilder, QuadHasFiveEdgesAndOneBendingSpring) {
  const BuiltObject o = buildMeshObject(specFor(loadObj(test::sourcePath("test/data/quad.obj"))));
  const Springs& sp = o.model.springs;
  EXPECT_EQ(o.model.familySize(SpringFamily::kStructural), 5);
  ASSERT_EQ(o.model.familySize(SpringFamily::kBending), 1);
  EXPECT_NEAR(o.model.mass.sum(), 0.3 * 1.0, 1e-15);
  // The quad is split along one diagonal: its two ends touch both triangles (mass 2 x 1/3 of
  // 0.15 kg); the bending spring joins the two other corners, across that diagonal.
  std::set<int> diagonal, across;
  for (std::size_t s = 0; s < sp.size(); ++s) {
    if (sp.family[s] == SpringFamily::kBending) across = {sp.first[s], sp.second[s]};
    else if (std::abs(sp.rest_length[s] - std::sqrt(2.0)) < 1e-12) diagonal = {sp.first[s], sp.second[s]};
  }
  ASSERT_EQ(diagonal.size(), 2u);
  ASSERT_EQ(across.size(), 2u);
  for (int v = 0; v < 4; ++v) {
    EXPECT_NE(diagonal.count(v), across.count(v)) << "vertex " << v;
    EXPECT_NEAR(o.model.mass[v], (diagonal.count(v) ? 2 : 1) * 0.3 * 0.5 / 3, 1e-15);
  }
}

TEST(MeshBuilder, DiscCountsFollowEuler) {
  const TriangleMesh disc = loadObj(test::sourcePath("config/meshes/round_cloth.obj"));
  const BuiltObject o = buildMeshObject(specFor(disc));
  // A disc: V - E + F = 1; every edge not on the boundary (120 of them) carries a bending spring.
  const int edges = disc.vertexCount() + disc.triangleCount() - 1;
  EXPECT_EQ(o.model.familySize(SpringFamily::kStructural), edges);
  EXPECT_EQ(o.model.familySize(SpringFamily::kBending), edges - 120);
  EXPECT_NO_THROW(o.model.validate());
}

TEST(MeshBuilder, GridTriangulationGivesTheGridsTriangleSprings) {
  // The mesh of a grid's own triangles yields exactly its structural + one-diagonal springs.
  GridSpec grid;
  grid.rows = 5;
  grid.cols = 6;
  grid.shear_pattern = ShearPattern::kTriangle;
  grid.material.areal_density = 0.3;
  const BuiltObject g = buildGrid(grid);
  const BuiltObject m = buildMeshObject(specFor(TriangleMesh{g.rest_positions, g.model.triangles}));
  auto edgeSet = [](const Model& model, bool bending) {
    std::set<std::tuple<int, int, long>> out;
    for (std::size_t s = 0; s < model.springs.size(); ++s) {
      if ((model.springs.family[s] == SpringFamily::kBending) != bending) continue;
      out.emplace(std::min(model.springs.first[s], model.springs.second[s]),
                  std::max(model.springs.first[s], model.springs.second[s]),
                  std::lround(1e9 * model.springs.rest_length[s]));
    }
    return out;
  };
  EXPECT_EQ(edgeSet(m.model, false), edgeSet(g.model, false));
  EXPECT_NEAR(m.model.mass.sum(), g.model.mass.sum(), 1e-12);
}

TEST(MeshBuilder, RefusesBadMeshesAndMaterial) {
  EXPECT_THROW(buildMeshObject(specFor(loadObj(test::sourcePath("test/data/nonmanifold.obj")))),
               std::invalid_argument);
  MeshSpec bad = specFor(loadObj(test::sourcePath("test/data/quad.obj")));
  bad.material.areal_density = 0.0;
  EXPECT_THROW(buildMeshObject(bad), std::invalid_argument);
}

TEST(MeshBuilder, HangingMeshReachesStaticEquilibrium) {
  // Physics through the mesh path: a quad pinned at two top corners settles where spring forces
  // balance gravity on every free vertex.
  MeshSpec spec = specFor(loadObj(test::sourcePath("test/data/quad.obj")).transformed(
      Eigen::Isometry3d(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitX())), 1.0));
  BuiltObject o = buildMeshObject(spec);
  o.model.damping = 5.0;
  PinSet pins;
  pins.add(2, o.rest_positions.col(2), 0.0, 4);
  pins.add(3, o.rest_positions.col(3), 0.0, 4);
  SimulationOptions options;
  options.settings = test::convergedSettings(100000, 1e-13);
  Simulation sim(o.model, o.rest_positions, pins, Colliders(), options);
  for (int k = 0; k < 600; ++k) ASSERT_EQ(sim.step().status, StepStatus::kOk);
  Points forces;
  totalForces(sim.model(), sim.pins(), sim.state().positions, forces);
  const double weight = o.model.mass[0] * 9.81;
  EXPECT_LT(forces.col(0).norm(), 1e-6 * weight);
  EXPECT_LT(forces.col(1).norm(), 1e-6 * weight);
  EXPECT_LT(sim.state().positions(2, 0), o.rest_positions(2, 0));  // and it did sag
}

}  // namespace
}  // namespace cloth_sim
