// The pair list of triangle self-contact (pair_list.h): over a run of small motions of a folded
// sheet it holds every pair the search of the paths finds within reach, it anchors again only
// the vertices that left their ball, it gives way to the search when a vertex moves more than
// twice its margin, and it lists the same pairs on any number of threads.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "cloth_sim/core/collision/pair_list.h"
#include "cloth_sim/core/collision/primitive_distance.h"
#include "cloth_sim/core/model/grid_builder.h"

namespace cloth_sim {
namespace {

constexpr double kThickness = 0.003;
constexpr double kReach = 1.25 * kThickness, kEdgeReach = 0.8 * kThickness;
constexpr double kMargin = 0.1 * kThickness;

/// A 40 x 40 sheet of 1 m folded in two along x = middle: the upper half 4 mm over the lower
/// one, wavy, so that the layers' pairs come and go within reach.
struct FoldedSheet {
  SurfaceTopology topology;
  Points start;
  explicit FoldedSheet(const BuiltObject& g)
      : topology(g.model.triangles, static_cast<int>(g.rest_positions.cols())),
        start(g.rest_positions) {
    const double middle = 0.5 * (start.row(0).minCoeff() + start.row(0).maxCoeff());
    for (int i = 0; i < start.cols(); ++i) {
      const double x = start(0, i), y = start(1, i);
      if (x > middle) {
        start(0, i) = 2.0 * middle - x;
        start(2, i) = 0.004 + 0.002 * std::sin(40.0 * x) * std::cos(30.0 * y);
      }
    }
  }
};

BuiltObject grid40() {
  GridSpec spec;
  spec.rows = spec.cols = 40;
  spec.width = spec.height = 1.0;
  return buildGrid(spec);
}

/// Closest distance of @p p at the positions (1 - s) a + s b (m).
double distanceAt(const PairCandidate& p, const Points& a, const Points& b, double s) {
  PairPoints x;
  for (int k = 0; k < 4; ++k) x[k] = (1.0 - s) * a.col(p.v[k]) + s * b.col(p.v[k]);
  return closestPoints(p.kind, x).distance;
}

/// Pairs of @p searched within their reach at the start, a quarter, the middle, three quarters
/// or the end of start -> end that @p listed lacks.
int missing(const std::vector<PairCandidate>& searched, const std::vector<PairCandidate>& listed,
            const Points& start, const Points& end) {
  const auto key = [](const PairCandidate& p) {
    return std::make_pair(static_cast<int>(p.kind), p.v);
  };
  std::vector<std::pair<int, std::array<int, 4>>> have;
  for (const PairCandidate& p : listed) have.push_back(key(p));
  std::sort(have.begin(), have.end());
  int lacking = 0;
  for (const PairCandidate& p : searched) {
    const double reach = p.kind == PairKind::kVertexTriangle ? kReach : kEdgeReach;
    bool near = false;
    for (const double s : {0.0, 0.25, 0.5, 0.75, 1.0}) near = near || distanceAt(p, start, end, s) <= reach;
    if (near && !std::binary_search(have.begin(), have.end(), key(p))) ++lacking;
  }
  return lacking;
}

TEST(PairList, HoldsEveryPairTheSearchFindsWithinReachOverSmallMotions) {
  const BuiltObject g = grid40();
  FoldedSheet sheet(g);
  const int n = static_cast<int>(sheet.start.cols());
  PairSearch search(sheet.topology, g.rest_positions), reference(sheet.topology, g.rest_positions);
  PairList list(search, kMargin);
  const unsigned seed = 20261127;
  std::printf("seed %u\n", seed);
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<PairCandidate> listed, searched;
  int served = 0, near_pairs = 0, partial = 0;
  Points start = sheet.start;
  for (int substep = 0; substep < 60; ++substep) {
    // Most vertices creep; one in ten moves up to 0.9 margin a substep, in a drift that makes
    // it leave its anchor's ball every few substeps; the upper layer sinks a little.
    Points end = start;
    for (int i = 0; i < n; ++i) {
      const double step = i % 10 == 0 ? 0.5 * kMargin : 0.02 * kMargin;
      for (int k = 0; k < 3; ++k) end(k, i) += step * unit(random);
      if (start(2, i) > 0.001) end(2, i) -= 0.01 * kMargin;
    }
    const bool used = list.find(search, sheet.topology, start, end, kReach, kEdgeReach, listed);
    served += used;
    partial += used && list.anchored() > 0 && list.anchored() < n;
    reference.find(sheet.topology, start, end, kReach, kEdgeReach, searched);
    ASSERT_EQ(missing(searched, listed, start, end), 0) << "substep " << substep;
    for (const PairCandidate& p : searched) {
      near_pairs += distanceAt(p, start, end, 0.5) <=
                    (p.kind == PairKind::kVertexTriangle ? kReach : kEdgeReach);
    }
    start = end;
  }
  std::printf("list served %d of 60 substeps (%d anchoring some vertices again), %d pairs "
              "within reach at the middle checked\n",
              served, partial, near_pairs);
  EXPECT_GT(near_pairs, 60 * 100);  // the layers are in contact: the check checks something
  EXPECT_GE(served, 50);
  EXPECT_GE(partial, 20);
}

TEST(PairList, AVertexMovingMoreThanTwiceTheMarginGoesToTheSearch) {
  const BuiltObject g = grid40();
  FoldedSheet sheet(g);
  PairSearch search(sheet.topology, g.rest_positions), reference(sheet.topology, g.rest_positions);
  PairList list(search, kMargin);
  std::vector<PairCandidate> listed, searched;
  Points end = sheet.start;
  ASSERT_TRUE(list.find(search, sheet.topology, sheet.start, end, kReach, kEdgeReach, listed));
  EXPECT_EQ(list.anchored(), static_cast<int>(sheet.start.cols()));
  end(2, 5) += 2.01 * kMargin;
  EXPECT_FALSE(list.find(search, sheet.topology, sheet.start, end, kReach, kEdgeReach, listed));
  reference.find(sheet.topology, sheet.start, end, kReach, kEdgeReach, searched);
  ASSERT_EQ(listed.size(), searched.size());
  for (std::size_t k = 0; k < listed.size(); ++k) EXPECT_EQ(listed[k].v, searched[k].v);
  // Within 2 m it serves again, anchoring that vertex (and no other) again.
  end(2, 5) = sheet.start(2, 5) + 1.9 * kMargin;
  EXPECT_TRUE(list.find(search, sheet.topology, sheet.start, end, kReach, kEdgeReach, listed));
  EXPECT_EQ(list.anchored(), 1);
}

TEST(PairList, ListsTheSamePairsOnAnyNumberOfThreads) {
  const BuiltObject g = grid40();
  FoldedSheet sheet(g);
  const int n = static_cast<int>(sheet.start.cols());
  std::vector<std::vector<PairCandidate>> runs;
  for (const int threads : {1, 2, 3}) {
    PairSearch search(sheet.topology, g.rest_positions);
    search.setThreads(threads);
    PairList list(search, kMargin);
    std::mt19937 random(7);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    std::vector<PairCandidate> listed, all;
    Points start = sheet.start;
    for (int substep = 0; substep < 20; ++substep) {
      Points end = start;
      for (int i = 0; i < n; i += 7) end(2, i) += 0.6 * kMargin * unit(random);
      list.find(search, sheet.topology, start, end, kReach, kEdgeReach, listed);
      all.insert(all.end(), listed.begin(), listed.end());
      start = end;
    }
    runs.push_back(all);
  }
  for (std::size_t r = 1; r < runs.size(); ++r) {
    ASSERT_EQ(runs[r].size(), runs[0].size());
    for (std::size_t k = 0; k < runs[0].size(); ++k) {
      ASSERT_TRUE(runs[r][k].kind == runs[0][k].kind && runs[r][k].v == runs[0][k].v) << k;
    }
  }
  std::printf("%zu pairs over 20 substeps, the same on 1, 2 and 3 threads\n", runs[0].size());
}

}  // namespace
}  // namespace cloth_sim
