// How the cost of a step grows with the number of dynamic spheres and with the cloth's size
// against a triangle-mesh obstacle.
#pragma once

#include <string>
#include <vector>

namespace cloth_sim::bench {

struct ScalingOptions {
  std::string scenes_dir;  ///< config/scenes
  std::string meshes_dir;  ///< config/meshes
  std::string out_dir;     ///< writes scaling.csv there
  double duration = 2.0;   ///< simulated s per case
  std::vector<int> sphere_counts{0, 1, 10, 100};
  std::vector<int> obstacle_grids{16, 32, 64, 128};
};

/// Spheres: the gravity_well sheet (49 x 49, chebyshev 15) with N balls (0.05 kg, r = 0.05 m)
/// dropped on it from a square layout. Obstacles: the drape cloth resized to g x g falling on
/// the table block (12 triangles) and on a flat disc of 2,400 triangles, with and without the
/// obstacle. Each case reports ms per step (median, p10, p90), the solver's share, and the
/// rest (collisions and contact forces outside the solver), per step and per cloth particle.
void runScaling(const ScalingOptions& options);

}  // namespace cloth_sim::bench
