// FrameError: a frame's substep errors summed per particle as vectors, RMS over the particles
// estimated.
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "cloth_sim/core/simulation/frame_error.h"

namespace cloth_sim {
namespace {

TEST(FrameError, AddsErrorsThatPointTheSameWayAndCancelsOppositeOnes) {
  FrameError frame;
  frame.begin(2);
  EXPECT_EQ(frame.rms(), 0.0) << "nothing estimated yet";
  Points e(3, 2);
  e << 1e-6, -2e-6,  //
      0.0, 0.0,      //
      0.0, 0.0;
  const std::vector<char> both = {1, 1};
  frame.add(e, both);
  frame.add(e, both);  // particle 0: 2e-6 m; particle 1: -4e-6 m
  EXPECT_NEAR(frame.rms(), std::sqrt((4e-12 + 16e-12) / 2.0), 1e-18);
  frame.add(-2.0 * e, both);  // back to zero: the errors cancelled
  EXPECT_NEAR(frame.rms(), 0.0, 1e-18);
}

TEST(FrameError, CountsOnlyTheParticlesSomeSubstepEstimated) {
  FrameError frame;
  frame.begin(3);
  Points e = Points::Constant(3, 3, 1e-6);
  frame.add(e, {1, 0, 0});
  EXPECT_NEAR(frame.rms(), std::sqrt(3.0) * 1e-6, 1e-18) << "particle 0 alone";
  frame.add(e, {0, 1, 0});
  EXPECT_NEAR(frame.rms(), std::sqrt(3.0) * 1e-6, 1e-18) << "particles 0 and 1, 1e-6 each";
  frame.begin(3);
  EXPECT_EQ(frame.rms(), 0.0) << "a new frame starts from zero";
  frame.add(Points::Constant(3, 5, 1e-6), {1, 1, 1, 1, 1});
  EXPECT_NEAR(frame.rms(), std::sqrt(3.0) * 1e-6, 1e-18) << "another count restarts the sum";
}

TEST(FrameError, NeverAboveTheSumOfTheSubstepsOwnRms) {
  const unsigned seed = 20261127;
  std::printf("[seed] %u\n", seed);
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1e-6);
  std::bernoulli_distribution skipped(0.2);
  for (int trial = 0; trial < 50; ++trial) {
    const int particles = 1 + trial % 7, substeps = 1 + trial % 5;
    FrameError frame;
    frame.begin(particles);
    double sum_of_rms = 0.0;
    for (int k = 0; k < substeps; ++k) {
      Points e(3, particles);
      std::vector<char> estimated(particles);
      double squares = 0.0;
      int count = 0;
      for (int i = 0; i < particles; ++i) {
        for (int d = 0; d < 3; ++d) e(d, i) = normal(rng);
        estimated[i] = skipped(rng) ? 0 : 1;
        if (estimated[i]) {
          squares += e.col(i).squaredNorm();
          ++count;
        }
      }
      frame.add(e, estimated);
      if (count > 0) sum_of_rms += std::sqrt(squares / count);
    }
    // Minkowski's inequality over the frame's counted particles, which are at least as many as
    // any substep's (a smaller count only raises that substep's own RMS).
    EXPECT_LE(frame.rms(), sum_of_rms * (1.0 + 1e-12)) << "trial " << trial;
  }
}

}  // namespace
}  // namespace cloth_sim
