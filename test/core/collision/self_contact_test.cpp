// The self-contact option and the object that runs its mode (self_contact.h): ranges, the
// automatic thickness, the modes, and the thickness the particle mode refuses.
#include <cmath>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "cloth_sim/core/collision/self_contact.h"
#include "cloth_sim/core/io/scene.h"
#include "cloth_sim/core/model/grid_builder.h"

namespace cloth_sim {
namespace {

TEST(SelfContactSettings, RangesAreTheTable) {
  SelfContactSettings s;
  EXPECT_NO_THROW(s.validate());
  EXPECT_EQ(s.mode, SelfContactMode::kTriangles);  // the default
  s.thickness = -0.01;
  EXPECT_THROW(s.validate(), std::invalid_argument);
  s.thickness = 0.01;
  s.friction = -1.0;
  try {
    s.validate();
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("self_collision.friction"), std::string::npos) << e.what();
  }
}

TEST(SelfContactSettings, ModesByName) {
  EXPECT_EQ(selfContactModeFromName("triangles"), SelfContactMode::kTriangles);
  EXPECT_EQ(selfContactModeFromName("particles"), SelfContactMode::kParticles);
  EXPECT_STREQ(selfContactModeName(SelfContactMode::kParticles), "particles");
  try {
    selfContactModeFromName("edges");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("triangles, particles"), std::string::npos) << e.what();
  }
}

TEST(SelfContact, AutomaticThickness) {
  GridSpec spec;
  spec.rows = spec.cols = 11;  // spacing 0.1 m: edges 0.1, 0.1 and 0.1 sqrt 2
  const BuiltObject g = buildGrid(spec);
  SelfContactSettings settings;
  settings.enabled = true;
  // Mode particles: the mean rest edge; mode triangles: 2 mm.
  settings.mode = SelfContactMode::kParticles;
  EXPECT_NEAR(SelfContact(g.model.triangles, g.rest_positions, settings).thickness(),
              0.1 * (2.0 + std::sqrt(2.0)) / 3.0, 1e-12);
  settings.mode = SelfContactMode::kTriangles;
  SelfContact triangles(g.model.triangles, g.rest_positions, settings);
  EXPECT_EQ(triangles.mode(), SelfContactMode::kTriangles);
  EXPECT_EQ(triangles.thickness(), kAutomaticThickness);
  // A cloth finer than 2 mm: its mean edge.
  spec.width = spec.height = 0.01;  // spacing 1 mm
  const BuiltObject fine = buildGrid(spec);
  EXPECT_NEAR(SelfContact(fine.model.triangles, fine.rest_positions, settings).thickness(),
              0.001 * (2.0 + std::sqrt(2.0)) / 3.0, 1e-15);
  settings.thickness = 0.003;
  EXPECT_EQ(SelfContact(g.model.triangles, g.rest_positions, settings).thickness(), 0.003);
}

TEST(SelfContact, TriangleModeRefusesAThicknessBelowItsFloor) {
  GridSpec spec;
  spec.rows = spec.cols = 5;
  const BuiltObject g = buildGrid(spec);
  SelfContactSettings settings;
  settings.thickness = 0.5 * kMinimumThickness;
  try {
    SelfContact(g.model.triangles, g.rest_positions, settings);
    FAIL() << "accepted";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("self_collision.thickness 5e-05 must be finite and >= 0.0001 m in mode "
                        "triangles"),
              std::string::npos)
        << what;
  }
  settings.thickness = kMinimumThickness;
  EXPECT_NO_THROW(SelfContact(g.model.triangles, g.rest_positions, settings));
}

TEST(SelfContact, TriangleModeHasNoDisplacementBound) {
  GridSpec spec;
  spec.rows = spec.cols = 5;
  const BuiltObject g = buildGrid(spec);
  SelfContactSettings settings;
  settings.thickness = 0.001;
  SelfContact contact(g.model.triangles, g.rest_positions, settings);
  ASSERT_NE(contact.triangles(), nullptr);
  EXPECT_EQ(contact.maxDisplacement(), std::numeric_limits<double>::infinity());
  const Eigen::VectorXd mass = Eigen::VectorXd::Constant(25, 0.01);
  const std::vector<char> movable(25, 1);
  const Points start = g.rest_positions;
  Points end = start, v = Points::Zero(3, 25);
  end.row(2).array() -= 1.0;  // 1 m in one substep: the bound of mode particles would cut it
  EXPECT_EQ(contact.limitDisplacement(CollisionStep{0.01, mass, movable, start}, end, v), 0);
  EXPECT_EQ(contact.resolve(CollisionStep{0.01, mass, movable, start}, GroundPlane{}, end, v), 0);
  EXPECT_LT((end - start).row(2).array().abs().maxCoeff() - 1.0, 1e-12);
  EXPECT_LT((end - start).topRows(2).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_TRUE(contact.contacts(end).empty());
  EXPECT_GE(contact.cpuSeconds(), 0.0);
}

/// The strip of the self-contact issue: 0.2 x 1.6 m, 10 x 64 particles (spacing 22 and 25 mm).
std::string stripScene(const std::string& self_collision) {
  return "time_step: 1/60\n"
         "cloth:\n  grid: {rows: 64, cols: 10, size: [0.2, 1.6], position: [0, 0, 0.85],"
         " orientation_rpy: [1.45, 0, 0]}\n"
         "material: {areal_density: 0.2, springs: {structural: 300, shear: 30, bending: 3}}\n"
         "colliders:\n  ground: {height: 0.0}\n"
         "self_collision: " + self_collision + "\n";
}

TEST(SelfContact, ParticleModeRefusesAThicknessItCannotKeepNamingTheRule) {
  // 1 cm is well under the strip's spacing: the particle mode used to accept it and let the
  // strip pass through itself (1425 intersecting pairs at 2 s); now it is refused with the rule.
  try {
    makeSimulation(parseScene(stripScene("{mode: particles, thickness: 0.01}"), "strip"));
    FAIL() << "accepted";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("self_collision.thickness 0.01 must be finite and >= "), std::string::npos)
        << what;
    EXPECT_NE(what.find("mode particles"), std::string::npos) << what;
    EXPECT_NE(what.find("1.05 x the widest gap"), std::string::npos) << what;
  }
  // What it can keep (>= 1.05 x the half diagonal of a 22 x 25 mm cell), and any thickness in
  // mode triangles.
  EXPECT_NO_THROW(
      makeSimulation(parseScene(stripScene("{mode: particles, thickness: 0.025}"), "strip")));
  EXPECT_NO_THROW(makeSimulation(parseScene(stripScene("{thickness: 0.001}"), "strip")));
  EXPECT_NO_THROW(
      makeSimulation(parseScene(stripScene("{mode: triangles, thickness: 0.01}"), "strip")));
}

TEST(SelfContact, SceneModeIsCheckedByName) {
  try {
    parseScene(stripScene("{mode: edges}"), "strip");
    FAIL() << "accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("self_collision.mode"), std::string::npos) << e.what();
  }
  const SceneConfig scene = parseScene(stripScene("{mode: particles}"), "strip");
  EXPECT_EQ(scene.options.self_contact.mode, SelfContactMode::kParticles);
  EXPECT_TRUE(scene.options.self_contact.enabled);
}

}  // namespace
}  // namespace cloth_sim
