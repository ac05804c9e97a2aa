#include <cmath>

#include <gtest/gtest.h>

#include "cloth_sim/core/collision/particle_self_contact.h"
#include "cloth_sim/core/model/grid_builder.h"

namespace cloth_sim {
namespace {

/// Two separate unit squares of 2 triangles each (vertices 0-3 and 4-7), the second 1 m to
/// the side at rest: no particle of one is a neighbour of the other.
struct TwoSheets {
  Eigen::Matrix3Xi triangles;
  Points rest;
  TwoSheets() : triangles(3, 4), rest(3, 8) {
    triangles << 0, 0, 4, 4, 1, 2, 5, 6, 2, 3, 6, 7;
    rest << 0, 1, 1, 0, 3, 4, 4, 3,  //
        0, 0, 1, 1, 0, 0, 1, 1,      //
        0, 0, 0, 0, 0, 0, 0, 0;
  }
};

struct StepData {
  Eigen::VectorXd mass;
  std::vector<char> movable;
  Points start;
  StepData(int n, const Points& s)
      : mass(Eigen::VectorXd::Constant(n, 0.1)), movable(n, 1), start(s) {}
  CollisionStep step(double h) const { return CollisionStep{h, mass, movable, start}; }
};

TEST(ParticleSelfContact, ParticlesOfTwoSheetsArePushedToTheThicknessWithMomentumKept) {
  const TwoSheets sheets;
  ParticleSelfContact contact(sheets.triangles, sheets.rest, 0.05, 0.0);
  // The second sheet lowered onto the first, 1 cm above it: each of its vertices 1 cm above one
  // of the first's.
  Points x = sheets.rest;
  for (int k = 4; k < 8; ++k) x.col(k) = sheets.rest.col(k - 4) + Vec3(0, 0, 0.01);
  StepData data(8, x);
  Points v = Points::Zero(3, 8);
  const Vec3 momentum_before = x.rowwise().sum();
  EXPECT_EQ(contact.contacts(x).size(), 4u);
  EXPECT_EQ(contact.resolve(data.step(0.01), GroundPlane{}, x, v), 8);
  for (int k = 0; k < 4; ++k) {
    EXPECT_NEAR((x.col(k + 4) - x.col(k)).norm(), 0.05, 1e-9);
    EXPECT_NEAR(v(2, k + 4), 2.0, 1e-6);  // 2 cm up in 0.01 s
  }
  EXPECT_LT((x.rowwise().sum() - momentum_before).norm(), 1e-12);  // equal masses, equal shares
  EXPECT_TRUE(contact.contacts(x).empty());
}

TEST(ParticleSelfContact, NeighboursPinnedParticlesAndTheGroundAreRespected) {
  GridSpec spec;
  spec.rows = spec.cols = 3;
  spec.width = spec.height = 0.02;  // spacing 1 cm, thickness 5 cm: every pair is near
  const BuiltObject g = buildGrid(spec);
  ParticleSelfContact contact(g.model.triangles, g.rest_positions, 0.05, 0.3);
  // Pairs that are not neighbours keep their rest distance (below t): nothing to do at rest.
  EXPECT_TRUE(contact.contacts(g.rest_positions).empty());

  const TwoSheets sheets;
  ParticleSelfContact sheet_contact(sheets.triangles, sheets.rest, 0.05, 0.3);
  Points x = sheets.rest;
  for (int k = 4; k < 8; ++k) x.col(k) = sheets.rest.col(k - 4) + Vec3(0, 0, 0.01);
  StepData data(8, x);
  for (int k = 0; k < 4; ++k) data.movable[k] = 0;  // the lower sheet hard-pinned
  Points v = Points::Zero(3, 8);
  sheet_contact.resolve(data.step(0.01), GroundPlane{}, x, v);
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(x.col(k), sheets.rest.col(k));  // pinned: never pushed
    EXPECT_NEAR(x(2, k + 4), 0.05, 1e-9);
  }
  // The upper sheet below the lower one, with the ground at 0: the ground wins, the lower sheet
  // (movable again) is pushed down to it and no further.
  x = sheets.rest;
  for (int k = 4; k < 8; ++k) x.col(k) = sheets.rest.col(k - 4) + Vec3(0, 0, 0.03);
  StepData free(8, x);
  GroundPlane ground;
  ground.enabled = true;
  sheet_contact.resolve(free.step(0.01), ground, x, v);
  for (int k = 0; k < 8; ++k) EXPECT_GE(x(2, k), 0.0);
  for (int k = 0; k < 4; ++k) EXPECT_GT((x.col(k + 4) - x.col(k)).norm(), 0.045);
}

TEST(ParticleSelfContact, FrictionHoldsASlideOfLessThanMuTimesTheCorrection) {
  const TwoSheets sheets;
  for (const double mu : {0.0, 1.0}) {
    ParticleSelfContact contact(sheets.triangles, sheets.rest, 0.05, mu);
    Points start = sheets.rest;
    for (int k = 4; k < 8; ++k) start.col(k) = sheets.rest.col(k - 4) + Vec3(0, 0, 0.05);
    StepData data(8, start);
    for (int k = 0; k < 4; ++k) data.movable[k] = 0;
    // The upper sheet moves 2 mm sideways and 2 cm down into the lower one.
    Points x = start;
    for (int k = 4; k < 8; ++k) x.col(k) += Vec3(0.002, 0, -0.02);
    Points v = Points::Zero(3, 8);
    contact.resolve(data.step(0.01), GroundPlane{}, x, v);
    for (int k = 4; k < 8; ++k) {
      // mu = 0: it slides on (and further, pushed out along the tilted line between the two);
      // mu = 1: the correction (2 cm) exceeds the slide, which is cut to a few micrometres.
      if (mu == 0.0)
        EXPECT_GT(x(0, k) - start(0, k), 0.002);
      else
        EXPECT_NEAR(x(0, k) - start(0, k), 0.0, 2e-5);
      EXPECT_GE((x.col(k) - x.col(k - 4)).norm(), 0.05 - 1e-12);
    }
  }
}

TEST(ParticleSelfContact, DisplacementIsBoundedAndVelocityFollows) {
  const TwoSheets sheets;
  const ParticleSelfContact contact(sheets.triangles, sheets.rest, 0.1, 0.3);
  StepData data(8, sheets.rest);
  data.movable[1] = 0;
  Points x = sheets.rest, v = Points::Zero(3, 8);
  x.col(0) += Vec3(0, 0, -0.5);   // 0.5 m in one substep: cut to 3 cm
  x.col(1) += Vec3(0, 0, -0.5);   // pinned: the pin decides
  x.col(2) += Vec3(0, 0, -0.02);  // within the bound
  v.col(0) = Vec3(0, 0, -50.0);
  EXPECT_EQ(contact.limitDisplacement(data.step(0.01), x, v), 1);
  EXPECT_NEAR(contact.maxDisplacement(), 0.03, 1e-15);
  EXPECT_NEAR((x.col(0) - sheets.rest.col(0)).norm(), 0.03, 1e-12);
  EXPECT_NEAR(v(2, 0), -3.0, 1e-9);
  EXPECT_NEAR(x(2, 1), -0.5, 1e-15);
  EXPECT_NEAR(x(2, 2), -0.02, 1e-15);
}

TEST(ParticleSelfContact, MinimumThicknessIsAboveTheWidestHole) {
  // A square grid of spacing s: right triangles, the widest hole is half the diagonal.
  GridSpec spec;
  spec.rows = spec.cols = 11;  // spacing 0.1 m
  const BuiltObject g = buildGrid(spec);
  EXPECT_NEAR(ParticleSelfContact::minimumThickness(g.model.triangles, g.rest_positions),
              1.05 * 0.1 / std::sqrt(2.0), 1e-12);
  // An acute (equilateral) triangle of side 1: its circumradius 1 / sqrt 3; an obtuse one: half
  // its longest side.
  Eigen::Matrix3Xi one(3, 1);
  one << 0, 1, 2;
  Points equilateral(3, 3), obtuse(3, 3);
  equilateral << 0, 1, 0.5, 0, 0, std::sqrt(3.0) / 2, 0, 0, 0;
  obtuse << 0, 2, 1, 0, 0, 0.2, 0, 0, 0;
  EXPECT_NEAR(ParticleSelfContact::minimumThickness(one, equilateral), 1.05 / std::sqrt(3.0), 1e-12);
  EXPECT_NEAR(ParticleSelfContact::minimumThickness(one, obtuse), 1.05, 1e-12);
}

}  // namespace
}  // namespace cloth_sim
