// Peers side by side with cloth_sim on the accuracy scenes: Bullet's implicit deformable solver
// (btDeformableMultiBodyDynamicsWorld, backward Euler by Newton + conjugate gradients) run on the
// same cloth and measured against the same true motion as `cloth_sim_bench accuracy`
// (docs/benchmark.md, "Bullet's implicit solver side by side"). Bullet is optional: without it
// (CLOTH_SIM_HAVE_BULLET undefined at build time) the subcommand says so and writes nothing.
#pragma once

#include <string>
#include <vector>

#include "cloth_sim/core/io/scene.h"

namespace cloth_sim::bench {

struct PeersOptions {
  std::string scenes_dir;   ///< config/scenes
  std::string untuned_dir;  ///< bench/scenes (flag and the other unshipped scenes)
  std::string out_dir;      ///< peers.csv
  std::string cache_dir;    ///< the accuracy benchmark's reference cache ('' = recompute)
  /// Scenes without colliders only: contacts are not mapped to Bullet (yet).
  std::vector<std::string> scenes = {"hanging", "flag"};
  std::vector<int> grids = {32};
  /// Bullet steps per frame (each one stepSimulation of frame / n, one implicit step).
  std::vector<int> substeps = {1, 2, 4, 8, 16, 32, 64};
  /// Newton iterations per step (0 = Bullet's own default).
  std::vector<int> newton_iterations = {0};
  double newton_tolerance = 0.0;  ///< Newton's residual norm test, kg m/s (0 = Bullet's)
  int krylov_iterations = 0;      ///< cap of each linear solve's iterations (0 = Bullet's)
  /// Bullet's "projection" mode (pins and contacts as velocity projections, CG with a mass
  /// preconditioner; its examples run the implicit solver so), not the world's default, the
  /// Lagrange multiplier mode (conjugate residual, KKT preconditioner): in that mode Bullet
  /// 3.24's implicit step left these cloths at rest (measured: no node moved). The strain
  /// limiting the world turns on with projections acts on face-rigid contacts only: none here.
  bool projection = true;
  /// Newton with Bullet's backtracking line search on its energy (off by default in Bullet).
  bool line_search = false;
  /// Diagnostic, not Bullet's method: Bullet's spring Hessian with its (1 - r / l) term
  /// clamped at 0 (label +psd), to test whether its indefiniteness is what blows up.
  bool clamped_hessian = false;
  std::vector<double> times = {0.25, 0.5, 1.0};
  std::string reference = "auto";  ///< as AccuracyOptions::reference
  int reference_substeps = 32;     ///< as AccuracyOptions::reference_substeps
  /// A configuration whose first frames take more CPU time than this per frame is stopped.
  double max_frame_ms = 1000.0;
};

/// "Bullet 3.24 (double precision)" when Bullet is built in, "" when it is not.
std::string bulletBuild();

/// One Bullet run of a scene: samples at the given frames and the cost of every frame.
struct PeerRun {
  std::vector<Points> positions;   ///< at each sample frame reached
  std::vector<Points> velocities;
  std::vector<double> frame_ms;      ///< wall time of every frame
  std::vector<double> frame_cpu_ms;  ///< CPU time of every frame (this thread)
  bool stopped = false;              ///< slower than max_frame_ms: not run to the end
  bool finite = true;                ///< every sampled position finite
  int newton_iterations = 0;         ///< the Newton cap Bullet ran with
  double newton_tolerance = 0.0;     ///< the residual test Bullet ran with
  int krylov_iterations = 0;         ///< the linear solves' cap Bullet ran with
};

struct BulletSettings {
  int substeps = 1;
  int newton_iterations = 0;     ///< 0 = Bullet's default
  double newton_tolerance = 0.0; ///< 0 = Bullet's default
  int krylov_iterations = 0;     ///< 0 = Bullet's default
  bool projection = true;  ///< PeersOptions::projection
  bool line_search = false;  ///< PeersOptions::line_search
  bool clamped_hessian = false;  ///< PeersOptions::clamped_hessian
};

/// Builds @p scene's cloth in Bullet (same particles, masses, springs, pins, gravity, damping;
/// see peers.cpp) and runs it frame by frame, sampling at the end of @p sample_frames
/// (increasing). Throws std::runtime_error when Bullet is not built in, or the scene has
/// colliders or soft pins (not mapped).
PeerRun runBullet(const SceneConfig& scene, const BulletSettings& settings,
                  const std::vector<int>& sample_frames, double max_frame_ms = 1e300);

/// Runs every scene x grid x Newton setting x substeps and writes peers.csv (the columns of
/// accuracy.csv, so one plot reads both); without Bullet, prints that it is absent.
void runPeers(const PeersOptions& options);

}  // namespace cloth_sim::bench
