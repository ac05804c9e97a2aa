// The randomized self-contact set at full size (docs/benchmark.md, "Self-collision"): the seeds
// of collision/self_contact_thin_scenes_test (strips, sheets, bags and folds at 1 to 10 mm,
// mode triangles) at 16 to 128 particles a side for 3 s, each frame checked for intersecting
// triangle pairs (StepReport::intersections). Too slow for a test (minutes at 128 x 128).
#pragma once

#include <string>

namespace cloth_sim::bench {

struct SelfCollisionSetOptions {
  std::string out_dir;            ///< self_collision_set.csv and .md
  unsigned first_seed = 20260500;  ///< the test's seeds
  int seeds = 20;
  int min_resolution = 16;  ///< particles along the longer side
  int max_resolution = 128;
  double seconds = 3.0;  ///< simulated time per case (s)
};

/// Runs each seed's case (cases::random) and writes one row per case to
/// out_dir/self_collision_set.csv and a table to self_collision_set.md: kind, thickness (mm),
/// resolution, frames, the most intersecting pairs of any frame and the first frame with one,
/// rolled-back frames, the closest vertex-triangle pair at the end (fraction of t, pairs at
/// least t apart at rest), max strain, and wall ms per frame with the self-contact and counter
/// shares. Prints one line per case. Returns the number of cases with an intersecting pair or a
/// rolled-back frame.
int runSelfCollisionSet(const SelfCollisionSetOptions& options);

}  // namespace cloth_sim::bench
