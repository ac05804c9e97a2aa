#include "stability.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "cases.h"
#include "cloth_sim/core/solvers/registry.h"
#include "stats.h"

namespace cloth_sim::bench {
namespace {

constexpr double kEventTime = 0.5;   ///< s: teleport / throw
constexpr double kEndWindow = 0.25;  ///< s: end_strain is the max over the run's last 0.25 s

}  // namespace

const char* scenarioName(Scenario s) {
  switch (s) {
    case Scenario::kRelease: return "release";
    case Scenario::kTeleport: return "teleport";
    case Scenario::kSphere: return "sphere";
  }
  return "unknown";
}

std::vector<std::string> defaultStabilitySolvers() {
  std::vector<std::string> solvers = solverNames();
  const std::string default_solver = SimulationOptions{}.solver;
  for (const Integrator integrator : kIntegrators) {
    if (integrator != SolverSettings{}.integrator &&
        solverEntry(default_solver).capabilities.supports(integrator)) {
      solvers.push_back(default_solver + "/" + integratorName(integrator));
    }
  }
  return solvers;
}

std::vector<std::string> stabilitySolverChoices() {
  std::vector<std::string> choices = solverNames();
  for (const SolverEntry& entry : solverRegistry()) {
    for (const Integrator integrator : kIntegrators) {
      if (integrator != SolverSettings{}.integrator && entry.capabilities.supports(integrator)) {
        choices.push_back(std::string(entry.name) + "/" + integratorName(integrator));
      }
    }
  }
  return choices;
}

SceneConfig stabilityScene(Scenario scenario, int grid, double stiffness, double time_step,
                           const std::string& solver, int iterations, double damping) {
  SceneConfig c;
  c.name = std::string("stability-") + scenarioName(scenario);
  c.source = c.name;
  c.grid.rows = grid;
  c.grid.cols = grid;
  c.grid.width = 1.0;
  c.grid.height = 1.0;
  c.grid.material.areal_density = 0.2;
  c.grid.material.structural = stiffness;
  c.grid.material.shear = stiffness / 10.0;
  c.grid.material.has_bending = true;
  c.grid.material.bending = stiffness / 100.0;
  // Horizontal at z = 1.5 m (release), or hanging in the x-z plane from z = 1.5 m down to 0.5 m.
  c.grid.pose = Eigen::Translation3d(0.0, 0.0, scenario == Scenario::kRelease ? 1.5 : 1.0) *
                Eigen::Isometry3d::Identity();
  if (scenario != Scenario::kRelease) {
    c.grid.pose = c.grid.pose * Eigen::AngleAxisd(M_PI / 2, Vec3::UnitX());
  }
  c.time_step = time_step;
  c.damping = damping;
  const std::size_t slash = solver.find('/');
  c.options.solver = solver.substr(0, slash);
  if (slash != std::string::npos) {
    c.options.settings.integrator = integratorFromName(solver.substr(slash + 1));
  }
  c.options.settings.max_iterations = iterations;
  c.options.settings.substeps = 1;  // each cell's time step is the implicit step
  for (int col = 0; col < grid; ++col) c.pins.push_back(PinSelector::atVertex(gridVertex(0, col, grid)));
  return fixedConfiguration(std::move(c));
}

CellResult runCell(Scenario scenario, int grid, double stiffness, double time_step,
                   const std::string& solver, int iterations, double duration, double damping) {
  Simulation sim = makeSimulation(
      stabilityScene(scenario, grid, stiffness, time_step, solver, iterations, damping));
  CellResult r;
  r.scenario = scenario;
  r.solver = solver;
  r.stiffness = stiffness;
  r.time_step = time_step;
  const int steps = static_cast<int>(std::lround(duration / time_step));
  const int event_step = static_cast<int>(std::lround(kEventTime / time_step));
  const int end_window = std::max(1, static_cast<int>(std::lround(kEndWindow / time_step)));
  for (int k = 1; k <= steps; ++k) {
    if (k == event_step + 1 && scenario == Scenario::kTeleport) {
      for (const Pin& pin : std::vector<Pin>(sim.pins().pins())) {
        sim.movePin(pin.id, pin.target + Vec3(0.0, 1.0, 0.0));
      }
    }
    if (k == event_step + 1 && scenario == Scenario::kSphere) {
      // Thrown from 1 m in front of the curtain, 0.2 m above its lower edge (z = 0.5 m).
      sim.addSphere(SphereCollider{-1, Vec3(0.0, -1.0, 0.7), 0.1, Vec3(0.0, 20.0, 0.0), 0.0});
    }
    const StepReport report = sim.step();
    r.steps = k;
    if (report.status != StepStatus::kOk) ++r.rollbacks;
    if (report.status == StepStatus::kNonFinite) r.finite = false;
    const double energy = sim.totalEnergy();
    r.peak_strain = std::max(r.peak_strain, report.max_strain);
    r.peak_energy = std::max(r.peak_energy, energy);
    if (k > steps - end_window) r.end_strain = std::max(r.end_strain, report.max_strain);
    r.end_energy = energy;
  }
  return r;
}

void runStability(const StabilityOptions& o) {
  std::filesystem::create_directories(o.out_dir);
  std::ofstream out(o.out_dir + "/stability.csv");
  out << "scenario,solver,stiffness,h,grid,iterations,steps,stable,rollbacks,finite,peak_strain,"
         "end_strain,peak_energy,end_energy\n";
  for (Scenario scenario : o.scenarios) {
    for (const std::string& solver : o.solvers) {
      for (double k : o.stiffness) {
        for (double h : o.time_steps) {
          const double t0 = now();
          const CellResult r =
              runCell(scenario, o.grid, k, h, solver, o.iterations, o.duration, o.damping);
          out << scenarioName(scenario) << ',' << solver << ',' << k << ',' << h << ',' << o.grid
              << ',' << o.iterations << ',' << r.steps << ',' << (r.stable() ? 1 : 0) << ','
              << r.rollbacks << ',' << (r.finite ? 1 : 0) << ',' << r.peak_strain << ','
              << r.end_strain << ',' << r.peak_energy << ',' << r.end_energy << '\n';
          out.flush();
          std::fprintf(stderr, "[stability] %-8s %-15s k %7.0e h 1/%-3.0f %-8s peak %8.3f end %8.3f "
                       "E %9.3g J (%.1f s)\n", scenarioName(scenario), solver.c_str(), k, 1.0 / h,
                       r.stable() ? "stable" : "UNSTABLE", r.peak_strain, r.end_strain,
                       r.end_energy, now() - t0);
        }
      }
    }
  }
}

}  // namespace cloth_sim::bench
