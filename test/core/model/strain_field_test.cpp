#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "cloth_sim/core/model/strain_field.h"

namespace cloth_sim {
namespace {

/// Four particles on the x axis, 1 m apart: 0-1 structural, 1-2 shear, 0-2 bending; 3 is free.
Model makeChain() {
  Model m;
  m.mass = Eigen::VectorXd::Ones(4);
  m.springs.add(0, 1, 1.0, 100.0, SpringFamily::kStructural);
  m.springs.add(1, 2, 1.0, 100.0, SpringFamily::kShear);
  m.springs.add(0, 2, 2.0, 10.0, SpringFamily::kBending);
  return m;
}

Points chainAt(double x1, double x2) {
  Points p(3, 4);
  p.col(0) << 0.0, 0.0, 0.0;
  p.col(1) << x1, 0.0, 0.0;
  p.col(2) << x2, 0.0, 0.0;
  p.col(3) << 5.0, 0.0, 0.0;
  return p;
}

TEST(StrainField, KeepsTheSignedStrainOfLargestMagnitude) {
  // 0-1 stretched by 10 %, 1-2 compressed by 30 %: particle 1 sees both and keeps -0.3.
  const Eigen::VectorXd e = vertexStrain(makeChain(), chainAt(1.1, 1.8));
  EXPECT_NEAR(e[0], 0.1, 1e-12);
  EXPECT_NEAR(e[1], -0.3, 1e-12);
  EXPECT_NEAR(e[2], -0.3, 1e-12);
  EXPECT_EQ(e[3], 0.0);  // no spring
}

TEST(StrainField, IgnoresBendingWhenInPlaneSpringsExist) {
  // Both in-plane springs at rest; the bending spring is compressed (a fold) but not counted.
  Points p = chainAt(1.0, 2.0);
  p.col(1) << 0.5, 0.0, std::sqrt(0.75);
  p.col(2) << 1.0, 0.0, 0.0;  // 0-2 at 1 m instead of 2 m, 1-2 still 1 m
  const Eigen::VectorXd e = vertexStrain(makeChain(), p);
  EXPECT_NEAR(e[0], 0.0, 1e-12);
  EXPECT_NEAR(e[2], 0.0, 1e-12);
}

TEST(StrainField, UsesEverySpringWhenThereIsNoInPlaneFamily) {
  Model m;
  m.mass = Eigen::VectorXd::Ones(4);
  m.springs.add(0, 2, 2.0, 10.0, SpringFamily::kBending);
  const Eigen::VectorXd e = vertexStrain(m, chainAt(1.0, 2.5));
  EXPECT_NEAR(e[0], 0.25, 1e-12);
  EXPECT_NEAR(e[2], 0.25, 1e-12);
  EXPECT_EQ(e[1], 0.0);
}

TEST(StrainField, NonFiniteStrainIsLeftOut) {
  Points p = chainAt(1.1, 2.1);
  p(0, 2) = std::numeric_limits<double>::quiet_NaN();
  const Eigen::VectorXd e = vertexStrain(makeChain(), p);
  EXPECT_TRUE(e.allFinite());
  EXPECT_NEAR(e[0], 0.1, 1e-12);  // 0-1 is fine
  EXPECT_EQ(e[2], 0.0);           // its only in-plane spring is NaN
}

TEST(StrainField, RefusesPositionsOfTheWrongSize) {
  EXPECT_THROW(vertexStrain(makeChain(), Points::Zero(3, 3)), std::invalid_argument);
}

}  // namespace
}  // namespace cloth_sim
