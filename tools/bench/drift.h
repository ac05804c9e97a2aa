// Energy drift of an undamped scene over a long run, per configuration (docs/benchmark.md,
// "Against XPBD on the peers' scene"): how much energy each integrator removes or adds.
#pragma once

#include <string>
#include <vector>

namespace cloth_sim::bench {

struct DriftOptions {
  std::string scenes_dir;  ///< config/scenes
  std::string out_dir;     ///< drift.csv
  std::string scene = "peer_cloth";
  int grid = 0;            ///< particles per side; 0 = the scene's own
  double duration = 10.0;  ///< s simulated
  /// "<solver>[/<integrator>]:<substeps>:<iterations>"; substeps "scene" = the scene's, "verlet"
  /// = velocity Verlet's half stability limit (as the accuracy reference); iterations "scene" =
  /// the scene's.
  std::vector<std::string> configs = {"local_global:scene:scene", "local_global/bdf2:scene:scene",
                                      "xpbd:scene:1", "verlet:verlet:1"};
};

/// Runs every configuration for options.duration and writes drift.csv (energy at the start, at
/// 1 s and at the end, its min and max over the frames, the largest kinetic energy, ms per frame)
/// into out_dir; prints one line per configuration.
void runDrift(const DriftOptions& options);

}  // namespace cloth_sim::bench
