// Additive CCD (additive_ccd.h): never reports a motion safe that comes closer than the minimum
// distance (checked by dense sampling over time), and finds the impacts of simple crossings.
#include <algorithm>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>

#include "cloth_sim/core/collision/additive_ccd.h"

namespace cloth_sim {
namespace {

/// Smallest distance of the pair over the motion's fraction [0, @p until], sampled.
double sampledMinimum(PairKind kind, const PairPoints& x0, const PairPoints& d, double until) {
  double best = 1e9;
  const int n = 2000;
  for (int i = 0; i <= n; ++i) {
    const double s = until * i / n;
    PairPoints x;
    for (int k = 0; k < 4; ++k) x[k] = x0[k] + s * d[k];
    best = std::min(best, closestPoints(kind, x).distance);
  }
  return best;
}

TEST(AdditiveCcd, VertexThroughTriangleStopsBeforeTheImpact) {
  const PairPoints x0 = {Vec3(0.2, 0.2, 1.0), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  const PairPoints d = {Vec3(0, 0, -2.0), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  // The vertex reaches 0.1 above the face at s = 0.45.
  const CcdResult r = additiveCcd(PairKind::kVertexTriangle, x0, d, 0.1);
  EXPECT_LT(r.safe_time, 0.45);
  EXPECT_GT(r.safe_time, 0.44);
  // Moving away or sideways far above: safe at once.
  const PairPoints up = {Vec3(0, 0, 2.0), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  EXPECT_EQ(additiveCcd(PairKind::kVertexTriangle, x0, up, 0.1).safe_time, 1.0);
  // A common translation of the four is no relative motion, however large.
  PairPoints together;
  for (auto& m : together) m = Vec3(5, -3, 7);
  EXPECT_EQ(additiveCcd(PairKind::kVertexTriangle, x0, together, 0.1).safe_time, 1.0);
  // Starting closer than the minimum distance: not even a start.
  EXPECT_EQ(additiveCcd(PairKind::kVertexTriangle, x0, d, 2.0).safe_time, 0.0);
}

TEST(AdditiveCcd, EdgesCrossingEachOtherAreFound) {
  // Edge 1 along x at z = 0.5 moving down through edge 2 along y at z = 0.
  const PairPoints x0 = {Vec3(-1, 0, 0.5), Vec3(1, 0, 0.5), Vec3(0, -1, 0), Vec3(0, 1, 0)};
  const PairPoints d = {Vec3(0, 0, -1), Vec3(0, 0, -1), Vec3::Zero(), Vec3::Zero()};
  const CcdResult r = additiveCcd(PairKind::kEdgeEdge, x0, d, 0.01);
  EXPECT_LT(r.safe_time, 0.49);
  EXPECT_GT(r.safe_time, 0.48);
  // Shifted sideways beyond the other edge's end: the same motion misses it.
  PairPoints beside = x0;
  for (int k = 0; k < 2; ++k) beside[k].y() += 1.5;
  EXPECT_EQ(additiveCcd(PairKind::kEdgeEdge, beside, d, 0.01).safe_time, 1.0);
}

TEST(AdditiveCcd, RandomMotionsNeverComeCloserThanReported) {
  std::mt19937 rng(20260401);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int hits = 0, iterations = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const PairKind kind = trial % 2 ? PairKind::kEdgeEdge : PairKind::kVertexTriangle;
    PairPoints x0, d;
    for (int k = 0; k < 4; ++k) {
      x0[k] = Vec3(u(rng), u(rng), u(rng));
      d[k] = 1.5 * Vec3(u(rng), u(rng), u(rng));
    }
    const double start = closestPoints(kind, x0).distance;
    const double min_distance = 0.25 * start * (0.5 + 0.5 * u(rng));
    const CcdResult r = additiveCcd(kind, x0, d, min_distance);
    iterations += r.iterations;
    EXPECT_GE(r.safe_time, 0.0);
    EXPECT_LE(r.safe_time, 1.0);
    // Up to the safe time the pair stays above the minimum distance.
    EXPECT_GE(sampledMinimum(kind, x0, d, r.safe_time), min_distance * (1.0 - 1e-9))
        << "trial " << trial;
    if (r.safe_time < 1.0) {
      ++hits;
      // A reported impact is real: shortly after the safe time the pair is close to the minimum.
      const double after = sampledMinimum(kind, x0, d, std::min(1.0, r.safe_time + 0.02));
      EXPECT_LT(after, min_distance + 0.2 * (start - min_distance) + 0.05) << "trial " << trial;
    }
  }
  std::printf("400 random pairs: %d impacts, %d distance evaluations after the first\n", hits,
              iterations);
  EXPECT_GT(hits, 20);
}

}  // namespace
}  // namespace cloth_sim
