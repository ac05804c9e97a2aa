#include "scaling.h"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <stdexcept>

#include "cloth_sim/core/collision/mesh_obstacle.h"
#include "cloth_sim/core/io/scene.h"
#include "cloth_sim/core/model/triangle_mesh.h"
#include "cases.h"
#include "stats.h"

namespace cloth_sim::bench {
namespace {

struct Timing {
  int particles = 0;
  std::size_t springs = 0;
  std::vector<double> step_ms, solve_ms, rest_ms;
  int failed = 0;
  double max_strain = 0.0;
};

Timing timeScene(const SceneConfig& config, double duration) {
  Simulation sim = makeSimulation(config);
  Timing t;
  t.particles = sim.model().particleCount();
  t.springs = sim.model().springs.size();
  const int steps = static_cast<int>(std::lround(duration / config.time_step));
  for (int s = 0; s < steps; ++s) {
    const StepReport r = sim.step();
    t.step_ms.push_back(1e3 * r.wall_time);
    t.solve_ms.push_back(1e3 * r.solve_time);
    t.rest_ms.push_back(1e3 * (r.wall_time - r.solve_time));
    if (r.status != StepStatus::kOk) ++t.failed;
    t.max_strain = std::max(t.max_strain, r.max_strain);
  }
  return t;
}

/// N balls on a square layout over the middle 1.8 m of the gravity_well sheet, 0.1 m up.
SceneConfig wellWithBalls(const std::string& scenes_dir, int count) {
  SceneConfig c = fixedConfiguration(loadSceneFile(scenes_dir + "/gravity_well.yaml"));
  c.spheres.clear();
  const int side = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(count))));
  for (int k = 0; k < count; ++k) {
    SphereCollider s;
    const double u = side > 1 ? (k % side) / double(side - 1) - 0.5 : 0.0;
    const double v = side > 1 ? (k / side) / double(side - 1) - 0.5 : 0.0;
    s.center = Vec3(1.8 * u, 1.8 * v, 0.1);
    s.radius = 0.05;
    s.mass = 0.05;
    s.friction = 0.1;
    s.restitution = 0.3;
    c.spheres.push_back(s);
  }
  return c;
}

/// The drape cloth at g x g, 0.15 m above an obstacle whose top is at z = 0.75, no sphere.
SceneConfig clothOver(const std::string& scenes_dir, int grid,
                      std::shared_ptr<const MeshObstacle> obstacle) {
  SceneConfig c = fixedConfiguration(loadSceneFile(scenes_dir + "/drape.yaml"));
  c.grid.rows = c.grid.cols = grid;
  c.grid.pose.translation() = Vec3(0.05, 0.02, 0.9);
  c.spheres.clear();
  c.meshes.clear();
  if (obstacle) c.meshes.push_back(MeshColliderSpec{"", std::move(obstacle)});
  return c;
}

}  // namespace

void runScaling(const ScalingOptions& o) {
  const std::string path = o.out_dir + "/scaling.csv";
  std::ofstream csv(path);
  if (!csv) throw std::runtime_error("cannot write " + path);
  csv << "case,parameter,particles,springs,spheres,obstacle_triangles,steps,ms_median,ms_p10,"
         "ms_p90,solve_ms_median,rest_ms_median,rest_us_per_particle,max_strain,failed_steps\n";
  auto record = [&](const std::string& name, int parameter, const SceneConfig& config,
                    int triangles) {
    const Timing t = timeScene(config, o.duration);
    const double rest = median(t.rest_ms);
    csv << name << ',' << parameter << ',' << t.particles << ',' << t.springs << ',' << config.spheres.size() << ',' << triangles << ','
        << t.step_ms.size() << ',' << median(t.step_ms) << ',' << quantile(t.step_ms, 0.1) << ','
        << quantile(t.step_ms, 0.9) << ',' << median(t.solve_ms) << ',' << rest << ','
        << 1e3 * rest / t.particles << ',' << t.max_strain << ',' << t.failed << '\n';
    csv.flush();
    std::cout << std::left << std::setw(16) << name << std::setw(6) << parameter
              << " ms/step " << std::setw(8) << median(t.step_ms) << " outside the solver "
              << rest << " ms, failed " << t.failed << "\n";
  };
  timeScene(wellWithBalls(o.scenes_dir, 0), 0.5);  // warm-up (caches, clock), not recorded
  for (int n : o.sphere_counts) record("spheres", n, wellWithBalls(o.scenes_dir, n), 0);

  const auto table = std::make_shared<const MeshObstacle>(
      loadObj(o.meshes_dir + "/table.obj"), 0.01, 0.4);
  Eigen::Isometry3d disc_pose = Eigen::Isometry3d::Identity();
  disc_pose.translation() = Vec3(0.0, 0.0, 0.75);
  const auto disc = std::make_shared<const MeshObstacle>(
      loadObj(o.meshes_dir + "/round_cloth.obj").transformed(disc_pose, 1.0), 0.01, 0.4);
  for (int g : o.obstacle_grids) {
    record("no_obstacle", g, clothOver(o.scenes_dir, g, nullptr), 0);
    record("table", g, clothOver(o.scenes_dir, g, table), table->mesh().triangleCount());
    record("disc", g, clothOver(o.scenes_dir, g, disc), disc->mesh().triangleCount());
  }
  std::cout << "wrote " << path << "\n";
}

}  // namespace cloth_sim::bench
