// Recovery of a cloth that already passes through itself (docs/method.md, "Self-contact",
// "Tangles"): a corner pin jumped 1 m down and back with self-collision off leaves the cloth
// crossing itself along a crease; with it still off the crease stays, with it turned on the
// untangling (intersection contour minimization) frees it within 2 s, for good.
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "cloth_sim/core/io/scene.h"
#include "test_util.h"

namespace cloth_sim {
namespace {

/// A 1 m cloth of @p n x @p n hanging from its two top corners, 8 substeps of 2 iterations.
std::string hanging(int n) {
  return "time_step: 1/60\nsolver: {name: local_global, iterations: 2, substeps: 8}\n"
         "cloth:\n  grid: {rows: " + std::to_string(n) + ", cols: " + std::to_string(n) +
         ", size: [1.0, 1.0], position: [0.0, 0.0, 1.5]}\n"
         "material: {areal_density: 0.2, damping: 0.1, springs: {structural: 400, shear: 40, "
         "bending: 4}}\npins:\n  - {row: 0, col: 0}\n  - {row: 0, col: " + std::to_string(n - 1) +
         "}\n";
}

struct Recovery {
  int tangled = 0;             ///< intersecting pairs when the option is turned on
  int frames_to_free = -1;     ///< frames until none is left (-1: never)
  int final_intersections = 0;
  int relapses = 0;            ///< frames with intersections after the first free one
  double final_strain = 0.0, quiet_strain = 0.0;
};

/// The pin jump with self-collision off (1 m down at 1 s, back at 2 s), then @p on_at_frame on
/// (or never: -1) with @p settings, @p frames in all.
Recovery jumpAndRecover(int n, int on_at_frame, int frames, const SelfContactSettings& settings) {
  Recovery r;
  Simulation quiet = makeSimulation(parseScene(hanging(n), "hanging"));
  for (int k = 0; k < frames; ++k) r.quiet_strain = quiet.step().max_strain;
  Simulation sim = makeSimulation(parseScene(hanging(n), "hanging"));
  const int pin = sim.pins().pins().front().id;
  const Vec3 home = sim.pins().find(pin)->target;
  for (int k = 1; k <= frames; ++k) {
    if (k == 60) sim.movePin(pin, home + Vec3(0, 0, -1.0));
    if (k == 120) sim.movePin(pin, home);
    if (k == on_at_frame) {
      r.tangled = sim.countIntersections();
      sim.setSelfContact(settings);
    }
    const StepReport report = sim.step();
    EXPECT_EQ(report.status, StepStatus::kOk) << report.message;
    r.final_strain = report.max_strain;
    if (on_at_frame < 0 || k < on_at_frame) continue;
    EXPECT_GE(report.intersections, 0);
    if (report.intersections == 0 && r.frames_to_free < 0) r.frames_to_free = k - on_at_frame + 1;
    if (report.intersections > 0 && r.frames_to_free >= 0) ++r.relapses;
  }
  r.final_intersections = sim.countIntersections();
  return r;
}

TEST(Untangling, APinJumpsCreaseStaysWithSelfCollisionOffAndUntanglesWithItOn) {
  SelfContactSettings on;
  on.enabled = true;
  on.thickness = 0.003;
  for (const int n : {20, 32}) {
    SCOPED_TRACE("n = " + std::to_string(n));
    const Recovery off = jumpAndRecover(n, -1, 420, on);
    const Recovery r = jumpAndRecover(n, 180, 420, on);  // on at 3 s, 4 s to recover
    std::printf(
        "%d x %d, pin jumped 1 m down and back: off: %d intersecting pairs at 7 s, max strain "
        "%.3f (undisturbed %.3f); turned on at 3 s over %d pairs: free after %d frames, %d "
        "frames with pairs after that, %d at 7 s, max strain %.3f\n",
        n, n, off.final_intersections, off.final_strain, off.quiet_strain, r.tangled,
        r.frames_to_free, r.relapses, r.final_intersections, r.final_strain);
    EXPECT_GT(off.final_intersections, 0);  // off: no recovery (measured, documented)
    EXPECT_GT(r.tangled, 0);
    EXPECT_GE(r.frames_to_free, 1);
    EXPECT_LE(r.frames_to_free, 120);  // free within 2 s
    EXPECT_EQ(r.relapses, 0);
    EXPECT_EQ(r.final_intersections, 0);
    // The strain is measured, not asserted: the local contour minimization chooses no side, and
    // the freed flap may end folded over the top edge (bending springs at 15-50 % of their
    // length; docs/method.md, "Tangles").
  }
}

}  // namespace
}  // namespace cloth_sim
