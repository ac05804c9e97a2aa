// Headless runner: steps a scene without ROS; per-step CSV or JSON, final positions, progress.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "cloth_sim/core/io/scene.h"
#include "cloth_sim/core/settings/settings_table.h"
#include "step_log.h"

namespace {

/// The most frames one run takes (about 19 days of simulated time at 60 Hz).
constexpr int kMaxFrames = 100000000;

struct Options {
  std::string scene_path, solver, linear_solver, integrator, csv, json, positions;
  std::optional<int> iterations, substeps;
  std::optional<double> dt, tolerance;
  double duration = 5.0;
  bool quiet = false, warm_start = false;
};

/// A CLI11 validator: a number in @p range, described by @p requirement (its rule and unit).
CLI::Validator inRange(cloth_sim::Range range, const std::string& requirement) {
  return CLI::Validator(
      [range, requirement](std::string& text) -> std::string {
        double v = 0.0;
        try {
          std::size_t used = 0;
          v = std::stod(text, &used);
          if (used != text.size()) return "'" + text + "' is not a number";
        } catch (const std::exception&) {
          return "'" + text + "' is not a number";
        }
        if (!range.contains(v)) return "value " + text + " must be " + requirement;
        return "";
      },
      requirement, "");
}

/// A CLI11 validator for the range of @p setting (settings_table.h).
CLI::Validator allowedBy(const cloth_sim::Setting& setting) {
  return inRange(setting.range, setting.requirement());
}

}  // namespace

int main(int argc, char** argv) {
  using namespace cloth_sim;
  CLI::App app{"cloth_sim headless runner: steps a scene file without ROS.\n"
               "Exit status: 0 ok, 1 bad arguments or scene, 2 some steps were rolled back."};
  Options o;
  app.add_option("--scene", o.scene_path, "scene YAML file")->required()->check(CLI::ExistingFile);
  app.add_option("--solver", o.solver, "solver (default: the scene's)")
      ->check(CLI::IsMember(solverNames()));
  app.add_option("--iterations", o.iterations, "iterations per step (default: the scene's)")
      ->check(allowedBy(settings::kIterations));
  app.add_option("--substeps", o.substeps,
                 "implicit steps of dt / substeps per frame (default: the scene's)")
      ->check(allowedBy(settings::kSubsteps));
  app.add_option("--dt", o.dt, "frame time step in s (default: the scene's)")
      ->check(allowedBy(settings::kTimeStep));
  app.add_option("--duration", o.duration, "simulated seconds (default 5)")
      ->check(inRange(Range::above(0), "> 0 s"));
  app.add_option("--tolerance", o.tolerance, "stop iterating below this relative change (0 = never)")
      ->check(allowedBy(settings::kTolerance));
  app.add_option("--linear-solver", o.linear_solver, "global step solve (default: fused)")
      ->check(CLI::IsMember(linearSolverNames()));
  app.add_option("--integrator", o.integrator,
                 "implicit_euler, bdf2 or implicit_midpoint (default: the scene's)")
      ->check(CLI::IsMember(integratorNames()));
  auto* csv = app.add_option("--csv", o.csv, "per-step CSV to this file ('-' = stdout)");
  app.add_option("--json", o.json, "per-step JSON to this file ('-' = stdout)")->excludes(csv);
  app.add_option("--positions", o.positions, "final positions (CSV: particle,x,y,z in m) to this file");
  app.add_flag("--warm-start", o.warm_start,
               "local_global, chebyshev, anderson, lbfgs: start from y + the previous step's correction");
  app.add_flag("--quiet", o.quiet, "no per-second summary on stdout");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 1;  // --help is 0; any bad argument is 1
  }

  try {
    SceneOverrides overrides;
    if (!o.solver.empty()) overrides.solver = o.solver;
    overrides.iterations = o.iterations;
    overrides.substeps = o.substeps;
    overrides.tolerance = o.tolerance;
    if (!o.linear_solver.empty()) overrides.linear_solver = linearSolverFromName(o.linear_solver);
    overrides.time_step = o.dt;
    if (!o.integrator.empty()) overrides.integrator = integratorFromName(o.integrator);
    if (o.warm_start) overrides.warm_start = true;
    const SceneConfig scene = applyOverrides(loadSceneFile(o.scene_path), overrides);
    Simulation sim = makeSimulation(scene);
    const double h = sim.frameTime();
    // A count derived from user numbers is checked before it is cast: 1e-10 s frames for 1 s
    // would overflow an int into a run of one step.
    const double frames = std::round(o.duration / h);
    if (!(frames <= kMaxFrames)) {
      throw std::invalid_argument("--duration " + std::to_string(o.duration) + " s at a frame of " +
                                  std::to_string(h) + " s is " + std::to_string(frames) +
                                  " frames, more than the " + std::to_string(kMaxFrames) +
                                  " a run can take");
    }
    const int steps = std::max(1, static_cast<int>(frames));
    const int per_second = static_cast<int>(std::clamp(std::round(1.0 / h), 1.0, frames + 1.0));
    const bool table_on_stdout = o.csv == "-" || o.json == "-";
    const bool summary = !o.quiet && !table_on_stdout;

    std::optional<tools::StepLog> log;
    if (!o.csv.empty()) log.emplace(o.csv, tools::StepLog::Format::kCsv);
    if (!o.json.empty()) log.emplace(o.json, tools::StepLog::Format::kJson);
    if (log) {
      log->begin(scene.name, sim.solver().name(), sim.model().particleCount(),
                 static_cast<int>(sim.model().springs.size()), h, sim.solverSettings().max_iterations);
    }
    if (summary) {
      std::printf("scene %s: %d particles, %zu springs, solver %s, %d substeps of %d iterations, "
                  "frame %.5f s\n",
                  scene.name.c_str(), sim.model().particleCount(), sim.model().springs.size(),
                  sim.solver().name(), sim.solverSettings().substeps,
                  sim.solverSettings().max_iterations, h);
    }
    tools::ProgressBar progress(steps);
    double wall = 0.0;
    int failures = 0;
    for (int k = 1; k <= steps; ++k) {
      tools::StepRecord record;
      record.report = sim.step();
      record.step = k;
      record.time = sim.state().time;
      record.energy = sim.totalEnergy();
      wall += record.report.wall_time;
      if (log) log->write(record);
      if (record.report.status != StepStatus::kOk) {
        ++failures;
        progress.finish();
        std::fprintf(stderr, "step %d: %s\n", k, record.report.message.c_str());
      }
      if (summary && (k % per_second == 0 || k == steps)) {
        progress.finish();
        std::printf("  t = %6.2f s  max strain %8.4f  energy %10.4f J  %.3f ms/step\n",
                    sim.state().time, record.report.max_strain, record.energy, 1e3 * wall / k);
        std::fflush(stdout);
      }
      progress.update(k, sim.state().time, 1e3 * wall / k);
    }
    progress.finish();
    if (log) log->end();
    if (!o.positions.empty()) tools::writePositions(o.positions, sim.state().positions);
    return failures == 0 ? 0 : 2;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
}
