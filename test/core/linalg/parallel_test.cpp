#include <atomic>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "cloth_sim/core/linalg/parallel.h"

namespace cloth_sim {
namespace {

TEST(Parallel, BlockSplitCoversTheRangeOnceInOrder) {
  for (std::size_t count : {0, 1, 7, 1024, 1025}) {
    const BlockSplit split(count, 256);
    std::size_t next = 0;
    for (int b = 0; b < split.blocks(); ++b) {
      EXPECT_EQ(split.begin(b), next);
      EXPECT_GT(split.end(b), split.begin(b));
      EXPECT_LE(split.end(b) - split.begin(b), 256u);
      next = split.end(b);
    }
    EXPECT_EQ(next, count);
  }
}

TEST(Parallel, EveryBlockRunsExactlyOnceOnAnyThreadCount) {
  for (int threads : {1, 2, 3, 8}) {
    std::vector<std::atomic<int>> runs(37);
    for (auto& r : runs) r = 0;
    parallelFor(threads, 37, [&](int b) { ++runs[b]; });
    for (int b = 0; b < 37; ++b) EXPECT_EQ(runs[b], 1) << "block " << b << ", threads " << threads;
  }
}

TEST(Parallel, OrderedSumIsTheSameBitsOnAnyThreadCount) {
  // Terms of very different size: any other order of addition changes the result's last bits.
  std::vector<double> terms(5000);
  for (std::size_t k = 0; k < terms.size(); ++k) terms[k] = std::pow(-1.3, k % 97) * (1.0 + 1e-9 * k);
  const BlockSplit split(terms.size(), 64);
  auto block_sum = [&](int b) {
    double s = 0.0;
    for (std::size_t k = split.begin(b); k < split.end(b); ++k) s += terms[k];
    return s;
  };
  const double one = orderedSum(1, split.blocks(), block_sum);
  for (int threads : {2, 3, 4, 7}) EXPECT_EQ(orderedSum(threads, split.blocks(), block_sum), one);
  double serial = 0.0;
  for (int b = 0; b < split.blocks(); ++b) serial += block_sum(b);
  EXPECT_EQ(one, serial);
}

TEST(Parallel, ZeroThreadsMeansEveryCore) {
  EXPECT_GE(availableCores(), 1);
  EXPECT_EQ(resolveThreads(0), availableCores());
  EXPECT_EQ(resolveThreads(3), 3);
}

}  // namespace
}  // namespace cloth_sim
