#include <cmath>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include "cloth_sim/core/model/spring_kernels.h"
#include "test_util.h"

namespace cloth_sim {
namespace {

TEST(SpringKernels, EnergyAndStrainKnownValues) {
  Springs s;
  s.add(0, 1, 1.0, 100.0, SpringFamily::kStructural);
  Points x(3, 2);
  x.col(0) = Vec3::Zero();
  x.col(1) = Vec3(0.0, 1.1, 0.0);
  EXPECT_NEAR(springEnergy(s, x), 0.5 * 100.0 * 0.01, 1e-12);
  EXPECT_NEAR(maxStrain(s, x), 0.1, 1e-12);
  x.col(1) = Vec3(0.0, 0.0, 0.7);  // compressed by 30 %
  EXPECT_NEAR(maxStrain(s, x), 0.3, 1e-12);
  x(0, 1) = NAN;
  EXPECT_TRUE(std::isnan(maxStrain(s, x)));  // NaN is reported, not swallowed
}

TEST(SpringKernels, ForcesAreMinusEnergyGradient) {
  const BuiltObject g = test::makeGrid(4, 5, 300.0, 30.0, 3.0);
  Points x = g.rest_positions + 0.05 * Points::Random(3, g.rest_positions.cols());
  Points f = Points::Zero(3, x.cols());
  addSpringForces(g.model.springs, x, f);
  const double eps = 1e-6;
  for (int i = 0; i < x.cols(); ++i) {
    for (int a = 0; a < 3; ++a) {
      Points xp = x, xm = x;
      xp(a, i) += eps;
      xm(a, i) -= eps;
      const double numeric =
          -(springEnergy(g.model.springs, xp) - springEnergy(g.model.springs, xm)) / (2 * eps);
      EXPECT_NEAR(f(a, i), numeric, 1e-6 * (1.0 + std::abs(numeric)));
    }
  }
  // Internal forces sum to zero (Newton's third law).
  EXPECT_LT(f.rowwise().sum().norm(), 1e-10);
}

TEST(SpringKernels, HessianIsExactInTensionAndPsdInCompression) {
  const double k = 50.0, r = 1.0, eps = 1e-6;
  const Vec3 stretched(0.3, 1.2, -0.4);  // |d| = 1.3 > r
  auto force = [&](const Vec3& d) { return Vec3(-k * (d.norm() - r) * d.normalized()); };
  const Eigen::Matrix3d hess = springHessianBlock(stretched, r, k);
  for (int b = 0; b < 3; ++b) {
    Vec3 e = Vec3::Zero();
    e[b] = eps;
    const Vec3 column = -(force(stretched + e) - force(stretched - e)) / (2 * eps);
    EXPECT_NEAR((hess.col(b) - column).norm(), 0.0, 1e-6);
  }
  const Vec3 compressed(0.1, 0.2, 0.3);  // |d| < r: exact Hessian is indefinite
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(springHessianBlock(compressed, r, k));
  EXPECT_GE(eig.eigenvalues().minCoeff(), -1e-12);
  EXPECT_NEAR(eig.eigenvalues().maxCoeff(), k, 1e-9);  // the axial stiffness survives
}

TEST(SpringKernels, SafeDirectionOfZero) {
  EXPECT_EQ(safeDirection(Vec3::Zero()), Vec3::UnitX());
  EXPECT_NEAR((safeDirection(Vec3(0, 3, 4)) - Vec3(0, 0.6, 0.8)).norm(), 0.0, 1e-15);
}

}  // namespace
}  // namespace cloth_sim
