// Closest points of a point and a triangle, and of two segments, against dense sampling.
#include <algorithm>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>

#include "cloth_sim/core/collision/primitive_distance.h"

namespace cloth_sim {
namespace {

Vec3 randomPoint(std::mt19937& rng, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  return Vec3(u(rng), u(rng), u(rng));
}

/// The closest points' weights describe points on the primitives whose distance is the one
/// returned, and no sample of the primitives is closer.
TEST(PrimitiveDistance, PointTriangleMatchesSampling) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 300; ++trial) {
    const Vec3 p = randomPoint(rng, 1.0), a = randomPoint(rng, 1.0), b = randomPoint(rng, 1.0);
    const Vec3 c = trial % 10 == 0 ? Vec3(0.5 * (a + b)) : randomPoint(rng, 1.0);  // degenerate
    const ClosestPoints cp = pointTriangle(p, a, b, c);
    EXPECT_NEAR(cp.weight[0] + cp.weight[1] + cp.weight[2] + cp.weight[3], 0.0, 1e-12);
    for (int k = 1; k < 4; ++k) EXPECT_LE(cp.weight[k], 1e-15);
    EXPECT_NEAR(gapVector(cp, p, a, b, c).norm(), cp.distance, 1e-12);
    double sampled = 1e9;
    const int n = 60;
    for (int i = 0; i <= n; ++i) {
      for (int j = 0; i + j <= n; ++j) {
        const Vec3 q = a + (double(i) / n) * (b - a) + (double(j) / n) * (c - a);
        sampled = std::min(sampled, (p - q).norm());
      }
    }
    EXPECT_LE(cp.distance, sampled + 1e-12);
    EXPECT_GE(cp.distance, sampled - 0.05);  // the sampling's own resolution
  }
}

TEST(PrimitiveDistance, SegmentSegmentMatchesSampling) {
  std::mt19937 rng(8);
  for (int trial = 0; trial < 300; ++trial) {
    const Vec3 p0 = randomPoint(rng, 1.0), p1 = randomPoint(rng, 1.0);
    Vec3 q0 = randomPoint(rng, 1.0), q1 = randomPoint(rng, 1.0);
    if (trial % 10 == 0) q1 = q0 + 0.7 * (p1 - p0);  // parallel
    if (trial % 10 == 1) q1 = q0;                    // a point
    const ClosestPoints cp = segmentSegment(p0, p1, q0, q1);
    EXPECT_NEAR(cp.weight[0] + cp.weight[1] + cp.weight[2] + cp.weight[3], 0.0, 1e-12);
    EXPECT_NEAR(gapVector(cp, p0, p1, q0, q1).norm(), cp.distance, 1e-12);
    double sampled = 1e9;
    const int n = 400;
    for (int i = 0; i <= n; ++i) {
      for (int j = 0; j <= n; j += 4) {
        const Vec3 a = p0 + (double(i) / n) * (p1 - p0), b = q0 + (double(j) / n) * (q1 - q0);
        sampled = std::min(sampled, (a - b).norm());
      }
    }
    EXPECT_LE(cp.distance, sampled + 1e-12);
    EXPECT_GE(cp.distance, sampled - 0.02);
  }
}

TEST(PrimitiveDistance, KnownCases) {
  // Above the face: straight down; beside an edge: to the edge.
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  ClosestPoints cp = pointTriangle(Vec3(0.25, 0.25, 0.5), a, b, c);
  EXPECT_NEAR(cp.distance, 0.5, 1e-15);
  EXPECT_NEAR(cp.weight[1], -0.5, 1e-15);
  cp = pointTriangle(Vec3(0.5, -1.0, 0.0), a, b, c);
  EXPECT_NEAR(cp.distance, 1.0, 1e-15);
  // Crossing segments one above the other.
  cp = segmentSegment(Vec3(-1, 0, 0.1), Vec3(1, 0, 0.1), Vec3(0, -1, 0), Vec3(0, 1, 0));
  EXPECT_NEAR(cp.distance, 0.1, 1e-15);
  EXPECT_NEAR(cp.weight[1], 0.5, 1e-15);
  EXPECT_NEAR(cp.weight[3], -0.5, 1e-15);
}

}  // namespace
}  // namespace cloth_sim
