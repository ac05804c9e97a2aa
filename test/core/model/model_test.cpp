#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "cloth_sim/core/model/model.h"
#include "test_util.h"

namespace cloth_sim {
namespace {

Model twoParticles() {
  Model m;
  m.mass = Eigen::Vector2d(1.0, 2.0);
  m.springs.add(0, 1, 0.5, 10.0, SpringFamily::kStructural);
  return m;
}

void expectInvalid(const Model& m, const std::string& needle) {
  try {
    m.validate();
    FAIL() << "expected rejection mentioning '" << needle << "'";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

TEST(Model, ValidModelPasses) { EXPECT_NO_THROW(twoParticles().validate()); }

TEST(Model, RejectsNamingTheBadField) {
  Model m = twoParticles();
  m.mass[1] = 0.0;
  expectInvalid(m, "mass[1]");
  m = twoParticles();
  m.springs.second[0] = 7;
  expectInvalid(m, "index out of range");
  m = twoParticles();
  m.springs.rest_length[0] = 0.0;
  expectInvalid(m, "rest length");
  m = twoParticles();
  m.springs.stiffness[0] = -1.0;
  expectInvalid(m, "stiffness");
  m = twoParticles();
  m.springs.first[0] = 1;
  expectInvalid(m, "itself");
  m = twoParticles();
  m.damping = std::numeric_limits<double>::quiet_NaN();
  expectInvalid(m, "damping");
}

TEST(Model, FamilyStiffnessTouchesOnlyThatFamily) {
  BuiltObject g = test::makeGrid(4, 4, 100.0, 10.0, 1.0);
  g.model.setFamilyStiffness(SpringFamily::kShear, 55.0);
  EXPECT_EQ(g.model.familyStiffness(SpringFamily::kShear), 55.0);
  EXPECT_EQ(g.model.familyStiffness(SpringFamily::kStructural), 100.0);
  EXPECT_EQ(g.model.familyStiffness(SpringFamily::kBending), 1.0);
  for (std::size_t s = 0; s < g.model.springs.size(); ++s) {
    if (g.model.springs.family[s] == SpringFamily::kShear) {
      EXPECT_EQ(g.model.springs.stiffness[s], 55.0);
    }
  }
}

TEST(State, AtRestAndFiniteness) {
  Points p = Points::Random(3, 5);
  State s = State::atRest(p);
  EXPECT_EQ(s.velocities.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_TRUE(s.allFinite());
  s.velocities(1, 3) = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(s.allFinite());
}

}  // namespace
}  // namespace cloth_sim
