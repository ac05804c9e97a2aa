#include <random>
#include <set>

#include <gtest/gtest.h>

#include "cloth_sim/core/collision/cell_hash.h"

namespace cloth_sim {
namespace {

TEST(CellHash, QueryFindsEveryKeyInTheBoxOnceAndOnlyNearbyOnes) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Points keys(3, 2000);
  for (Eigen::Index k = 0; k < keys.cols(); ++k) keys.col(k) = Vec3(u(rng), u(rng), 0.1 * u(rng));
  CellHash hash;
  hash.build(keys, 0.05);
  ASSERT_EQ(hash.size(), 2000);
  for (int q = 0; q < 50; ++q) {
    const Vec3 c(u(rng), u(rng), 0.0);
    const Eigen::AlignedBox3d box(c - Vec3::Constant(0.07), c + Vec3::Constant(0.07));
    std::multiset<int> seen;
    hash.query(box, [&](int id) { seen.insert(id); });
    for (Eigen::Index k = 0; k < keys.cols(); ++k) {
      const bool inside = box.contains(Vec3(keys.col(k)));
      if (inside) {
        EXPECT_EQ(seen.count(static_cast<int>(k)), 1u) << "key " << k;
      }
      // A visited key is at most one cell outside the box.
      if (seen.count(static_cast<int>(k)) > 0) {
        EXPECT_LE(box.exteriorDistance(Vec3(keys.col(k))), 0.05 * std::sqrt(3.0) + 1e-12);
      }
    }
    for (int id : seen) EXPECT_EQ(seen.count(id), 1u);
  }
}

TEST(CellHash, AHugeBoxVisitsEveryItemOnceAndBadInputIsRefused) {
  Points keys(3, 3);
  keys << 0, 10, -5, 0, 0, 3, 0, 1, 2;
  CellHash hash;
  hash.build(keys, 1e-3);  // the box below spans far more cells than there are items
  std::multiset<int> seen;
  hash.query(Eigen::AlignedBox3d(Vec3::Constant(-20), Vec3::Constant(20)),
             [&](int id) { seen.insert(id); });
  EXPECT_EQ(seen, (std::multiset<int>{0, 1, 2}));
  EXPECT_THROW(hash.build(keys, 0.0), std::invalid_argument);
  keys(0, 1) = std::nan("");
  EXPECT_THROW(hash.build(keys, 1.0), std::invalid_argument);
  hash.build(Points(3, 0), 1.0);  // empty: queries visit nothing
  int visits = 0;
  hash.query(Eigen::AlignedBox3d(Vec3::Zero(), Vec3::Ones()), [&](int) { ++visits; });
  EXPECT_EQ(visits, 0);
}

}  // namespace
}  // namespace cloth_sim
