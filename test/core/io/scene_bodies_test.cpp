// The scene's rigid bodies (colliders.bodies[], scene_bodies.h): read, placed or put on a frame,
// built into the simulation; each bad field refused by name.
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "cloth_sim/core/io/scene.h"
#include "test_util.h"

namespace cloth_sim {
namespace {

const char* kCloth = R"(cloth: {grid: {rows: 4, cols: 4, size: [0.3, 0.3], position: [0, 0, 1]}}
material: {springs: {structural: 100}}
)";

SceneConfig scene(const std::string& bodies) {
  return parseScene(std::string(kCloth) + "colliders:\n  bodies:\n" + bodies, "bodies.yaml");
}

std::string refusal(const std::string& bodies) {
  try {
    scene(bodies);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(SceneBodies, ReadsStillAndFrameBodies) {
  const SceneConfig s = scene(
      "    - {name: table, shape: box, size: [1, 0.6, 0.04], position: [0, 0, 0.7], friction: 0.5}\n"
      "    - {shape: capsule, radius: 0.01, length: 0.05, frame: tool0, position: [0, 0, 0.1],"
      " margin: 0.002}\n"
      "    - {shape: sphere, radius: 0.05, frame: wrist, orientation_rpy: [0, 1.5707963267948966, 0]}\n");
  ASSERT_EQ(s.bodies.size(), 3u);
  EXPECT_EQ(s.bodies[0].name, "table");
  EXPECT_FALSE(s.bodies[0].follows_frame);
  EXPECT_DOUBLE_EQ(s.bodies[0].pose().translation().z(), 0.7);
  EXPECT_DOUBLE_EQ(s.bodies[0].friction, 0.5);
  EXPECT_EQ(s.bodies[1].name, "tool0");
  EXPECT_TRUE(s.bodies[1].follows_frame);
  EXPECT_DOUBLE_EQ(s.bodies[1].origin.translation().z(), 0.1);
  EXPECT_DOUBLE_EQ(s.bodies[1].margin, 0.002);
  EXPECT_TRUE((s.bodies[2].origin.linear() * Vec3::UnitZ()).isApprox(Vec3::UnitX()));
  const Simulation sim = makeSimulation(s);
  ASSERT_EQ(sim.colliders().bodies().bodies().size(), 3u);
  EXPECT_FALSE(sim.colliders().bodies().bodies()[1].placed);  // nowhere until its frame is seen
}

TEST(SceneBodies, ReadsAMeshBodyFromAnObjFile) {
  const SceneConfig s = parseScene(std::string(kCloth) +
                                       "colliders: {bodies: [{shape: mesh, file: ../meshes/table.obj,"
                                       " scale: 0.5, margin: 0.01}]}\n",
                                   test::sourcePath("config/scenes/x.yaml"));
  ASSERT_EQ(s.bodies.size(), 1u);
  EXPECT_DOUBLE_EQ(s.bodies[0].geometry.mesh->thickness(), 0.01);
  EXPECT_GT(s.bodies[0].geometry.mesh->mesh().triangleCount(), 0);
}

TEST(SceneBodies, RefusesEachBadFieldByName) {
  EXPECT_NE(refusal("    - {shape: cone}\n").find("colliders.bodies[0].shape"), std::string::npos);
  EXPECT_NE(refusal("    - {size: [1, 1, 1]}\n").find("colliders.bodies[0].shape': is required"),
            std::string::npos);
  EXPECT_NE(refusal("    - {shape: box}\n").find("colliders.bodies[0].size': is required for a box"),
            std::string::npos);
  EXPECT_NE(refusal("    - {shape: box, size: [1, 0, 1]}\n")
                .find("'colliders.bodies[0].size': value 0 must be in (0, 1e+06] m"),
            std::string::npos);
  EXPECT_NE(refusal("    - {shape: sphere, radius: -1}\n").find("colliders.bodies[0].radius"),
            std::string::npos);
  EXPECT_NE(refusal("    - {shape: capsule, radius: 0.1, length: .nan}\n")
                .find("colliders.bodies[0].length"),
            std::string::npos);
  EXPECT_NE(refusal("    - {shape: sphere, radius: 0.1, margin: 2}\n")
                .find("colliders.bodies[0].margin': value 2 must be in (0, 1] m"),
            std::string::npos);
  EXPECT_NE(refusal("    - {shape: sphere, radius: 0.1, friction: -1}\n")
                .find("colliders.bodies[0].friction"),
            std::string::npos);
  EXPECT_NE(refusal("    - {shape: mesh, file: missing.stl}\n").find("colliders.bodies[0].file"),
            std::string::npos);
  EXPECT_NE(refusal("    - {shape: sphere, radius: 0.1, frame: ''}\n")
                .find("colliders.bodies[0].frame': must name a frame"),
            std::string::npos);
  EXPECT_NE(refusal("    - {shape: sphere, radius: 0.1, colour: red}\n").find("colour"),
            std::string::npos);
}

}  // namespace
}  // namespace cloth_sim
