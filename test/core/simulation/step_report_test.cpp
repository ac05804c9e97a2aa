// The frame check: a frame is kept unless a position, velocity or strain is not finite (cloth or
// sphere) or the strain is above the divergence limit; the rollback message says which.
#include <cmath>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "cloth_sim/core/simulation/step_report.h"

namespace cloth_sim {
namespace {

TEST(StepReport, StatusNames) {
  EXPECT_STREQ(stepStatusName(StepStatus::kOk), "ok");
  EXPECT_STREQ(stepStatusName(StepStatus::kNonFinite), "non_finite");
  EXPECT_STREQ(stepStatusName(StepStatus::kDiverged), "diverged");
}

TEST(StepReport, FrameStatusFromFinitenessAndStrain) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  State s = State::atRest(Points::Zero(3, 2));
  Colliders colliders;
  EXPECT_EQ(frameStatus(s, colliders, 0.5, 1.0), StepStatus::kOk);
  EXPECT_EQ(frameStatus(s, colliders, 1.0, 1.0), StepStatus::kOk);  // at the limit: kept
  EXPECT_EQ(frameStatus(s, colliders, 1.5, 1.0), StepStatus::kDiverged);
  EXPECT_EQ(frameStatus(s, colliders, nan, 1.0), StepStatus::kNonFinite);
  State bad = s;
  bad.velocities(1, 1) = nan;
  EXPECT_EQ(frameStatus(bad, colliders, 0.5, 1.0), StepStatus::kNonFinite);
  const int id = colliders.addSphere(SphereCollider{-1, Vec3(0, 0, 1), 0.1});
  EXPECT_EQ(frameStatus(s, colliders, 0.5, 1.0), StepStatus::kOk);
  colliders.mutableSpheres()[0].angular_velocity.x() = std::numeric_limits<double>::infinity();
  EXPECT_EQ(frameStatus(s, colliders, 0.5, 1.0), StepStatus::kNonFinite) << "sphere " << id;
  EXPECT_EQ(frameStatus(s, colliders, 1.5, 1.0), StepStatus::kNonFinite);  // non-finite wins
}

TEST(StepReport, RollbackMessageNamesTheSolverTheStrainAndTheTime) {
  const std::string diverged =
      rollbackMessage(StepStatus::kDiverged, "explicit_euler", 150.0, 100.0, 2.5);
  EXPECT_NE(diverged.find("explicit_euler diverged: max strain 150 > limit 100"), std::string::npos)
      << diverged;
  EXPECT_NE(diverged.find("at t = 2.5 s; rolled back"), std::string::npos) << diverged;
  const std::string non_finite = rollbackMessage(StepStatus::kNonFinite, "newton", 0.0, 100.0, 1.0);
  EXPECT_NE(non_finite.find("newton produced a non-finite position or velocity"), std::string::npos)
      << non_finite;
}

}  // namespace
}  // namespace cloth_sim
