#include "drift.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "accuracy.h"
#include "cases.h"
#include "stats.h"

namespace cloth_sim::bench {
namespace {

/// 1/2 sum_i m_i |v_i|^2 (J).
double kineticEnergy(const Simulation& sim) {
  return 0.5 * sim.state().velocities.colwise().squaredNorm().dot(sim.model().mass);
}

/// Splits "a:b:c" at ':'.
std::vector<std::string> fields(const std::string& text) {
  std::vector<std::string> out(1);
  for (char ch : text) {
    if (ch == ':') out.emplace_back();
    else out.back() += ch;
  }
  return out;
}

}  // namespace

void runDrift(const DriftOptions& o) {
  std::filesystem::create_directories(o.out_dir);
  std::ofstream csv(o.out_dir + "/drift.csv");
  csv << "case,solver,substeps,iterations,duration,energy_start,energy_1s,energy_end,drift,"
         "energy_min,energy_max,kinetic_max,frame_ms_median,frame_ms_p10,frame_ms_p90,rollbacks\n";
  SceneConfig scene = fixedConfiguration(loadSceneFile(o.scenes_dir + "/" + o.scene + ".yaml"));
  std::string name = o.scene + "-" + std::to_string(scene.grid.rows);
  if (o.grid > 0) {
    BenchCase c = makeCase(o.scenes_dir, o.scene, o.grid);
    c.config.options.settings.substeps = scene.options.settings.substeps;  // makeCase sets 1
    scene = c.config;
    name = c.name;
  }
  for (const std::string& text : o.configs) {
    const std::vector<std::string> f = fields(text);
    if (f.size() != 3) throw std::invalid_argument("drift config '" + text + "': want solver:substeps:iterations");
    SceneOverrides overrides;
    const std::size_t slash = f[0].find('/');
    overrides.solver = f[0].substr(0, slash);
    overrides.integrator = slash == std::string::npos ? Integrator::kImplicitEuler
                                                      : integratorFromName(f[0].substr(slash + 1));
    if (f[1] == "verlet")
      overrides.substeps = verletSubsteps(scene);
    else if (f[1] != "scene")
      overrides.substeps = std::stoi(f[1]);
    if (f[2] != "scene") overrides.iterations = std::stoi(f[2]);
    const SceneConfig config = applyOverrides(scene, overrides);
    Simulation sim = makeSimulation(config);
    const int frames = static_cast<int>(o.duration / sim.frameTime() + 0.5);
    const int one_second = static_cast<int>(1.0 / sim.frameTime() + 0.5);
    const double e0 = sim.totalEnergy();
    double e1 = e0, e_min = e0, e_max = e0, k_max = 0.0;
    int rollbacks = 0;
    std::vector<double> frame_ms;
    for (int k = 1; k <= frames; ++k) {
      const double start = now();
      if (sim.step().status != StepStatus::kOk) ++rollbacks;
      frame_ms.push_back(1e3 * (now() - start));
      const double e = sim.totalEnergy();
      e_min = std::min(e_min, e);
      e_max = std::max(e_max, e);
      k_max = std::max(k_max, kineticEnergy(sim));
      if (k == one_second) e1 = e;
    }
    const double end = sim.totalEnergy();
    const std::string label = f[0];
    csv << name << ',' << label << ',' << config.options.settings.substeps << ','
        << config.options.settings.max_iterations << ',' << o.duration << ',' << e0 << ',' << e1
        << ',' << end << ',' << end - e0 << ',' << e_min << ',' << e_max << ',' << k_max << ','
        << median(frame_ms) << ',' << quantile(frame_ms, 0.1) << ',' << quantile(frame_ms, 0.9)
        << ',' << rollbacks << '\n';
    csv.flush();
    std::printf("%s %s s%d i%d: energy %.4f J at 0, %.4f J at 1 s, %.4f J at %g s (drift %+.4f J; "
                "kinetic max %.3f J), %.2f ms per frame, %d rollbacks\n",
                name.c_str(), label.c_str(), config.options.settings.substeps,
                config.options.settings.max_iterations, e0, e1, end, o.duration, end - e0, k_max,
                median(frame_ms), rollbacks);
    std::fflush(stdout);
  }
}

}  // namespace cloth_sim::bench
