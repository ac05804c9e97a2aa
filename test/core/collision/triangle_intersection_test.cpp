#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "cloth_sim/core/collision/triangle_intersection.h"
#include "cloth_sim/core/model/grid_builder.h"

namespace cloth_sim {
namespace {

TEST(TriangleIntersection, CrossingTouchingAndApartTriangles) {
  const Vec3 a0(0, 0, 0), a1(1, 0, 0), a2(0, 1, 0);
  // A vertical triangle piercing the first one.
  EXPECT_TRUE(trianglesIntersect(a0, a1, a2, Vec3(0.2, 0.2, -0.5), Vec3(0.2, 0.2, 0.5),
                                 Vec3(0.3, 0.25, 0.5)));
  // The same one lifted just above: no intersection.
  EXPECT_FALSE(trianglesIntersect(a0, a1, a2, Vec3(0.2, 0.2, 1e-9), Vec3(0.2, 0.2, 1.0),
                                  Vec3(0.3, 0.25, 1.0)));
  // Crossing the plane outside the triangle.
  EXPECT_FALSE(trianglesIntersect(a0, a1, a2, Vec3(0.8, 0.8, -0.5), Vec3(0.8, 0.8, 0.5),
                                  Vec3(0.9, 0.9, 0.5)));
  // Two layers one above the other, parallel: apart.
  EXPECT_FALSE(
      trianglesIntersect(a0, a1, a2, Vec3(0, 0, 0.01), Vec3(1, 0, 0.01), Vec3(0, 1, 0.01)));
  // Touching at one point (a vertex on the face): not counted.
  EXPECT_FALSE(trianglesIntersect(a0, a1, a2, Vec3(0.2, 0.2, 0.0), Vec3(0.2, 0.3, 1.0),
                                  Vec3(0.3, 0.2, 1.0)));
  // An edge through the interior while no vertex of either is inside the other ("X" shape).
  EXPECT_TRUE(trianglesIntersect(Vec3(-1, 0.3, 0), Vec3(2, 0.3, 0), Vec3(0.5, 0.3, 3),
                                 a0 + Vec3(0, 0, -1), Vec3(0.5, 2, 1), Vec3(0.5, -2, 1)));
  EXPECT_TRUE(segmentCrossesTriangle(Vec3(0.1, 0.1, -1), Vec3(0.1, 0.1, 1), a0, a1, a2));
  EXPECT_FALSE(segmentCrossesTriangle(Vec3(0.1, 0.1, 0), Vec3(0.1, 0.1, 1), a0, a1, a2));
}

/// A grid of n x n on [-0.5, 0.5]^2 folded about x = 0 by @p angle (rad): the half x > 0 turns
/// up by pi - angle; angle 0 = flat, pi = folded flat onto itself, > pi passes through.
Points folded(const BuiltObject& g, double angle, double gap) {
  Points x = g.rest_positions;
  for (Eigen::Index k = 0; k < x.cols(); ++k) {
    const double r = x(0, k);
    if (r <= 0.0) continue;
    const double turn = angle;
    x(0, k) = r * std::cos(turn);
    x(2, k) = r * std::sin(turn) + gap * r;
  }
  return x;
}

TEST(IntersectionCounter, FlatAndFoldedClothHaveNoneAndAClothThroughItselfHasMany) {
  GridSpec spec;
  spec.rows = spec.cols = 21;
  const BuiltObject g = buildGrid(spec);
  IntersectionCounter counter(g.model.triangles);
  EXPECT_EQ(counter.count(g.rest_positions), 0);
  EXPECT_EQ(counter.count(folded(g, 2.0, 0.0)), 0);  // bent up by 115 deg
  EXPECT_EQ(counter.count(folded(g, 3.1, 0.0)), 0);  // almost flat on itself
  // The right half rotated below the left half's plane and back up through it.
  Points through = g.rest_positions;
  for (Eigen::Index k = 0; k < through.cols(); ++k) {
    const double r = through(0, k);
    if (r > 0.0) {
      through(0, k) = 0.25 - r;                   // folded over onto the left half...
      through(2, k) = 0.05 * std::sin(40.0 * r);  // ...weaving through it
    }
  }
  const auto pairs = counter.pairs(through);
  EXPECT_GT(pairs.size(), 10u);
  EXPECT_EQ(counter.count(through), static_cast<int>(pairs.size()));
  for (const auto& [s, t] : pairs) EXPECT_LT(s, t);
  // Non-finite positions count nothing (the simulation rolls such a frame back).
  through(0, 3) = std::nan("");
  EXPECT_EQ(counter.count(through), 0);
}

TEST(IntersectionCounter, HashedCountEqualsBruteForceWithHugeTriangles) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int n = 300;
  Points x(3, 3 * n);
  Eigen::Matrix3Xi tri(3, n);
  for (int t = 0; t < n; ++t) {
    const Vec3 c(u(rng), u(rng), u(rng));
    const double size = t % 50 == 0 ? 1.0 : 0.2;  // a few triangles far larger than the rest
    for (int k = 0; k < 3; ++k) {
      x.col(3 * t + k) = c + size * Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5);
      tri(k, t) = 3 * t + k;
    }
  }
  int brute = 0;
  for (int s = 0; s < n; ++s)
    for (int t = s + 1; t < n; ++t) {
      const auto v = [&](int k, int tr) { return Vec3(x.col(tri(k, tr))); };
      brute += trianglesIntersect(v(0, s), v(1, s), v(2, s), v(0, t), v(1, t), v(2, t));
    }
  IntersectionCounter counter(tri);
  EXPECT_GT(brute, 20);
  EXPECT_EQ(counter.count(x), brute);
}

}  // namespace
}  // namespace cloth_sim
