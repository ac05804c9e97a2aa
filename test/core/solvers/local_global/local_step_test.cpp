#include <cmath>

#include <gtest/gtest.h>

#include "cloth_sim/core/solvers/local_global/local_step.h"
#include "cloth_sim/core/model/spring_kernels.h"
#include "test_util.h"

namespace cloth_sim {
namespace {

TEST(LocalStep, AccumulatesJdAndReturnsTheSpringEnergy) {
  BuiltObject g = test::makeGrid(5, 6, 300.0, 30.0, 3.0);
  const int n = g.model.particleCount();
  const Points x = g.rest_positions + 0.05 * Points::Random(3, n);
  const double h2 = 1e-3;
  const Springs& springs = g.model.springs;
  SpringTable table;
  for (std::size_t s = 0; s < springs.size(); ++s) {
    table.add(springs.first[s], springs.second[s], h2 * springs.stiffness[s] * springs.rest_length[s],
              springs.stiffness[s], springs.rest_length[s]);
  }
  table.sortByNode();
  NodeBuffer xb(kNodeStride * n, 0.0), rhs(kNodeStride * n, 0.0);
  for (int i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) xb[kNodeStride * i + c] = x(c, i);
  const double energy = localStep3(table, xb.data(), rhs.data());

  Points expected = Points::Zero(3, n);  // J d = sum_s k_s r_s u_s (A_s), eq. 12 without h^2
  for (std::size_t s = 0; s < springs.size(); ++s) {
    const Vec3 d = springs.rest_length[s] * safeDirection(x.col(springs.first[s]) - x.col(springs.second[s]));
    expected.col(springs.first[s]) += h2 * springs.stiffness[s] * d;
    expected.col(springs.second[s]) -= h2 * springs.stiffness[s] * d;
  }
  for (int i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(rhs[kNodeStride * i + c], expected(c, i), 1e-14);
    EXPECT_EQ(rhs[kNodeStride * i + 3], 0.0);
  }
  EXPECT_NEAR(energy, springEnergy(springs, x), 1e-12 * energy);
  EXPECT_NEAR(springEnergy3(table, xb.data()), energy, 1e-12 * energy);
}

TEST(LocalStep, CollapsedSpringPushesAlongPlusX) {
  SpringTable table;
  table.add(0, 1, 2.0, 10.0, 0.5);
  NodeBuffer x(2 * kNodeStride, 0.0), rhs(2 * kNodeStride, 0.0);
  const double energy = localStep3(table, x.data(), rhs.data());
  EXPECT_EQ(rhs[0], 2.0);
  EXPECT_EQ(rhs[kNodeStride], -2.0);
  EXPECT_EQ(rhs[1], 0.0);
  EXPECT_DOUBLE_EQ(energy, 0.5 * 10.0 * 0.25);
}

TEST(LocalStep, CollapsedSpringAmongFourTakesTheSameFallback) {
  // The vector path handles springs four at a time and must fall back for a collapsed one.
  SpringTable table;
  for (int s = 0; s < 9; ++s) table.add(s, s + 1, 1.0 + s, 10.0, 0.5);
  NodeBuffer x(10 * kNodeStride, 0.0), rhs(10 * kNodeStride, 0.0);
  for (int i = 0; i < 10; ++i) x[kNodeStride * i + 1] = (i == 6 ? 5 : i) * 0.5;  // nodes 5, 6 coincide
  double expected_energy = 0.0;
  NodeBuffer expected(rhs.size(), 0.0);
  for (int s = 0; s < 9; ++s) {
    const double d = x[kNodeStride * s + 1] - x[kNodeStride * (s + 1) + 1];
    const int axis = d == 0.0 ? 0 : 1;
    const double push = (1.0 + s) * (d == 0.0 ? 1.0 : (d > 0 ? 1.0 : -1.0));
    expected[kNodeStride * s + axis] += push;
    expected[kNodeStride * (s + 1) + axis] -= push;
    expected_energy += 5.0 * std::pow(std::abs(d) - 0.5, 2);
  }
  EXPECT_DOUBLE_EQ(localStep3(table, x.data(), rhs.data()), expected_energy);
  for (std::size_t k = 0; k < rhs.size(); ++k) EXPECT_DOUBLE_EQ(rhs[k], expected[k]) << k;
}

TEST(LocalStep, PartitionedStepIsTheSameSumInBlocksAndTheSameBitsOnAnyThreads) {
  BuiltObject g = test::makeGrid(30, 30, 300.0, 30.0, 3.0);
  const int n = g.model.particleCount();
  const Springs& springs = g.model.springs;
  SpringTable table;
  for (std::size_t s = 0; s < springs.size(); ++s) {
    table.add(springs.first[s], springs.second[s], 1e-3 * springs.stiffness[s] * springs.rest_length[s],
              springs.stiffness[s], springs.rest_length[s]);
  }
  table.sortByNode();
  NodeBuffer x(kNodeStride * n, 0.0);
  const Points p = g.rest_positions + 0.05 * Points::Random(3, n);
  for (int i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) x[kNodeStride * i + c] = p(c, i);
  x[kNodeStride * 7] = x[kNodeStride * 8];  // a collapsed spring (7, 8) among the others
  x[kNodeStride * 7 + 1] = x[kNodeStride * 8 + 1];
  x[kNodeStride * 7 + 2] = x[kNodeStride * 8 + 2];
  NodeBuffer whole(x.size(), 0.0);
  const double energy = localStep3(table, x.data(), whole.data());

  table.partition(n, 37);  // odd blocks: many boundary springs
  ASSERT_GT(table.blocks(), 20);
  ASSERT_GT(table.out_begin.back(), 100) << "boundary springs";
  NodeBuffer one(x.size(), 0.0);
  const double energy_one = localStep3(table, x.data(), one.data(), 1);
  EXPECT_NEAR(energy_one, energy, 1e-13 * energy);
  EXPECT_NEAR(springEnergy3(table, x.data(), 1), energy, 1e-13 * energy);
  Vec3 total = Vec3::Zero();  // every push enters once with + and once with -
  for (int i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(one[kNodeStride * i + c], whole[kNodeStride * i + c], 1e-14) << i;
      total[c] += one[kNodeStride * i + c];
    }
    EXPECT_EQ(one[kNodeStride * i + 3], 0.0);
  }
  EXPECT_LT(total.norm(), 1e-14);
  for (int threads : {2, 3, 5}) {
    NodeBuffer many(x.size(), 0.0);
    EXPECT_EQ(localStep3(table, x.data(), many.data(), threads), energy_one) << threads;
    EXPECT_EQ(many, one) << threads;
    EXPECT_EQ(springEnergy3(table, x.data(), threads), springEnergy3(table, x.data(), 1));
  }
}

TEST(LocalStep, InertiaAndGravityMatchesItsDefinition) {
  NodeBuffer x = {1, 2, 3, 0, -1, 0, 2, 0}, y = {1, 1, 1, 0, 0, 0, 0, 0};
  const std::vector<double> mass = {2.0, 3.0};
  const Vec3 gravity(0, 0, -10);
  const double h2 = 0.01;
  const double expected = 2.0 * (0.5 * 5.0 - h2 * -30.0) + 3.0 * (0.5 * 5.0 - h2 * -20.0);
  EXPECT_DOUBLE_EQ(inertiaAndGravity(x.data(), y.data(), mass.data(), 2, gravity, h2), expected);
  // Many nodes: blocks summed in order, the same bits on any threads.
  const int count = 5000;
  NodeBuffer xs(kNodeStride * count), ys(kNodeStride * count);
  std::vector<double> masses(count);
  for (int k = 0; k < count; ++k) {
    masses[k] = 1.0 + 1e-3 * k;
    for (int c = 0; c < 3; ++c) {
      xs[kNodeStride * k + c] = std::sin(k + c);
      ys[kNodeStride * k + c] = std::cos(3 * k + c);
    }
  }
  const double one = inertiaAndGravity(xs.data(), ys.data(), masses.data(), count, gravity, h2, 1);
  for (int threads : {2, 3}) {
    EXPECT_EQ(inertiaAndGravity(xs.data(), ys.data(), masses.data(), count, gravity, h2, threads), one);
  }
}

}  // namespace
}  // namespace cloth_sim
