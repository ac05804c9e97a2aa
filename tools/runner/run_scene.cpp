// Headless runner: steps a scene without ROS; per-step CSV or JSON, final positions, progress.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cloth_sim/core/io/scene.h"
#include "cloth_sim/core/settings/settings_table.h"
#include "cloth_sim/core/solvers/registry.h"
#include "fold_script.h"
#include "step_log.h"

namespace {

struct Options {
  std::string scene_path, solver, linear_solver, integrator, csv, json, positions;
  std::optional<int> iterations, substeps, threads;
  std::optional<double> dt, tolerance, error_tolerance, fold;
  double frame_deadline_ms = 0.0;
  std::optional<int> resolution;
  std::string self_collision;
  double duration = 5.0;
  bool quiet = false, warm_start = false, check = false;
};

/// Values longer than this are cut in messages: a 100 kB argument is not echoed back whole.
constexpr std::size_t kShown = 64;

/// @p text, or its first kShown characters and how long it was.
std::string clip(const std::string& text) {
  if (text.size() <= kShown) return text;
  return text.substr(0, kShown) + "... (" + std::to_string(text.size()) + " characters)";
}

/// A CLI11 validator: a number @p setting (settings_table.h) allows; its refusal otherwise
/// ("value 0 must be in [1, 100000]", after CLI11's "--iterations: ").
CLI::Validator allowedBy(const cloth_sim::Setting& setting) {
  return CLI::Validator(
      [&setting](std::string& text) -> std::string {
        // strtod, not stod: a denormal such as 5e-324 is a number (out of range, not "not one").
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        if (text.empty() || end != text.c_str() + text.size()) {
          return "'" + clip(text) + "' is not a number";
        }
        return setting.refusal(v, "value");
      },
      setting.requirement(), "");
}

/// @p names as "a, b, c".
std::string listed(const std::vector<std::string>& names) {
  std::string list;
  for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
  return list;
}

/// A CLI11 validator: @p names lists the allowed values (checked here, so that a long value is
/// quoted cut, and the list is given).
CLI::Validator oneOf(const std::vector<std::string>& names) {
  const std::string list = listed(names);
  return CLI::Validator(
      [names, list](std::string& text) -> std::string {
        if (std::find(names.begin(), names.end(), text) != names.end()) return "";
        return "'" + clip(text) + "' is not one of " + list;
      },
      "one of " + list, "");
}

/// A CLI11 validator: an existing file, its name cut in the message.
const CLI::Validator kExistingFile(
    [](std::string& path) -> std::string {
      return std::ifstream(path) ? "" : "cannot read '" + clip(path) + "'";
    },
    "FILE", "");

/// Runs @p open (which writes option @p option's file @p path); its failure names the option.
template <class Open>
void openNamed(const char* option, const std::string& path, Open open) {
  try {
    open();
  } catch (const std::exception&) {
    throw std::runtime_error(std::string(option) + ": cannot write '" + clip(path) + "'");
  }
}

}  // namespace

int main(int argc, char** argv) {
  using namespace cloth_sim;
  CLI::App app{"cloth_sim headless runner: steps a scene file without ROS.\n"
               "Exit status: 0 ok, 1 bad arguments or scene, 2 some steps were rolled back."};
  Options o;
  app.add_option("--scene", o.scene_path, "scene YAML file")->required()->check(kExistingFile);
  app.add_option("--solver", o.solver, "solver (default: the scene's)")
      ->check(oneOf(solverNames()));
  app.add_option("--iterations", o.iterations, "iterations per step (default: the scene's)")
      ->check(allowedBy(settings::kIterations));
  app.add_option("--substeps", o.substeps,
                 "implicit steps of dt / substeps per frame (default: the scene's)")
      ->check(allowedBy(settings::kSubsteps));
  app.add_option("--dt", o.dt, "frame time step in s (default: the scene's)")
      ->check(allowedBy(settings::kTimeStep));
  app.add_option("--duration", o.duration, "simulated seconds (default 5)")
      ->check(allowedBy(settings::kRunDuration));
  app.add_option("--tolerance", o.tolerance, "stop iterating below this relative change (0 = never)")
      ->check(allowedBy(settings::kTolerance));
  app.add_option("--threads", o.threads,
                 "threads of the kernels, 0 = every core (default: the scene's solver.threads); "
                 "the results are the same for any count")
      ->check(allowedBy(settings::kThreads));
  app.add_option("--error-tolerance", o.error_tolerance,
                 "position error a frame may make, m (0 = fixed iterations; with --substeps 0 the "
                 "substeps follow it too)")
      ->check(allowedBy(settings::kErrorTolerance));
  app.add_option("--linear-solver", o.linear_solver, "global step solve (default: fused)")
      ->check(oneOf(linearSolverNames()));
  app.add_option("--integrator", o.integrator,
                 "implicit_euler, bdf2 or implicit_midpoint (default: the scene's)")
      ->check(oneOf(integratorNames()));
  auto* csv = app.add_option("--csv", o.csv, "per-step CSV to this file ('-' = stdout)");
  app.add_option("--json", o.json, "per-step JSON to this file ('-' = stdout)")->excludes(csv);
  app.add_option("--positions", o.positions, "final positions (CSV: particle,x,y,z in m) to this file");
  app.add_flag("--warm-start", o.warm_start,
               listed(solverNamesWith(&SolverCapabilities::warm_start)) +
                   ": start from y + the previous step's correction");
  app.add_flag("--quiet", o.quiet, "no per-second summary on stdout");
  app.add_option("--self-collision", o.self_collision,
                 "on or off (default: the scene's self_collision)")
      ->check(CLI::IsMember({"on", "off"}));
  app.add_option("--resolution", o.resolution,
                 "grid cloth: rows = cols = this, pins moved to the same place on the sheet; "
                 "self_collision.thickness becomes automatic in mode particles")
      ->check(allowedBy(settings::kGridResolution));
  app.add_option("--fold", o.fold,
                 "carry the scene's first pin over the cloth to the vertex farthest from it in "
                 "this many s, then let go (the fold scene's script)")
      ->check(allowedBy(settings::kFoldTime));
  app.add_option("--frame-deadline-ms", o.frame_deadline_ms,
                 "wall-clock ms a frame may take before its work is cut: iterations stop and its "
                 "remaining substeps run as one (0 = never, the default: the same results on any "
                 "machine); the CSV's cut_substeps and merged_substeps say when")
      ->check(allowedBy(settings::kFrameDeadline));
  app.add_flag("--check", o.check,
               "load and build the scene with the options, run nothing: exit 0 if it can be run");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help
    // CLI11's own messages quote the value whole: cut, as every message here.
    const std::string what = e.what();
    std::cerr << (what.size() <= 4 * kShown ? what : what.substr(0, 4 * kShown) + "... (cut)")
              << "\nRun with --help for more information.\n";
    return 1;  // any bad argument is 1
  }

  try {
    SceneOverrides overrides;
    if (!o.solver.empty()) overrides.solver = o.solver;
    overrides.iterations = o.iterations;
    overrides.substeps = o.substeps;
    overrides.threads = o.threads;
    overrides.tolerance = o.tolerance;
    overrides.error_tolerance = o.error_tolerance;
    if (!o.linear_solver.empty()) overrides.linear_solver = linearSolverFromName(o.linear_solver);
    overrides.time_step = o.dt;
    if (!o.integrator.empty()) overrides.integrator = integratorFromName(o.integrator);
    if (o.warm_start) overrides.warm_start = true;
    if (!o.self_collision.empty()) overrides.self_collision = o.self_collision == "on";
    overrides.resolution = o.resolution;
    SceneConfig loaded;
    try {
      loaded = loadSceneFile(o.scene_path);
    } catch (const std::exception& e) {
      const std::string what = e.what();  // long only when the path is: cut it then
      throw std::runtime_error("--scene " + (what.size() <= 16 * kShown ? what : clip(what)));
    }
    SceneConfig scene;
    try {
      scene = applyOverrides(std::move(loaded), overrides);
    } catch (const SceneError& e) {  // only --resolution can be refused here
      throw std::runtime_error(std::string("--resolution: ") + e.what());
    }
    Simulation sim = makeSimulation(scene);
    sim.setFrameDeadline(1e-3 * o.frame_deadline_ms);
    if (o.check) return 0;  // the scene and the options are usable (scripts/run_demo.sh)
    std::optional<tools::FoldScript> fold;
    if (o.fold) fold.emplace(sim, *o.fold);
    const double h = sim.frameTime();
    // A count derived from user numbers is checked before it is cast: 1e-10 s frames for 1 s
    // would overflow an int into a run of one step.
    const double frames = std::round(o.duration / h);
    if (!settings::kRunFrames.allows(frames)) {
      throw std::invalid_argument("--duration " + formatNumber(o.duration) +
                                  " s at a frame (--dt, else the scene's time_step) of " +
                                  formatNumber(h) +
                                  " s: " + settings::kRunFrames.refusal(frames, "frames"));
    }
    const int steps = static_cast<int>(frames);
    const int per_second = static_cast<int>(std::clamp(std::round(1.0 / h), 1.0, frames + 1.0));
    const bool table_on_stdout = o.csv == "-" || o.json == "-";
    const bool summary = !o.quiet && !table_on_stdout;

    std::optional<tools::StepLog> log;
    if (!o.csv.empty()) {
      openNamed("--csv", o.csv, [&] { log.emplace(o.csv, tools::StepLog::Format::kCsv); });
    }
    if (!o.json.empty()) {
      openNamed("--json", o.json, [&] { log.emplace(o.json, tools::StepLog::Format::kJson); });
    }
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
    int failures = 0, cut_frames = 0;
    for (int k = 1; k <= steps; ++k) {
      tools::StepRecord record;
      if (fold) fold->beforeStep(sim);
      record.report = sim.step();
      record.step = k;
      record.time = sim.state().time;
      record.energy = sim.totalEnergy();
      wall += record.report.wall_time;
      cut_frames += record.report.shortfall() ? 1 : 0;
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
    if (summary && cut_frames > 0) {
      std::printf("%d of %d frames cut at the %g ms --frame-deadline-ms\n", cut_frames, steps,
                  o.frame_deadline_ms);
    }
    if (log) log->end();
    if (!o.positions.empty()) {
      openNamed("--positions", o.positions,
                [&] { tools::writePositions(o.positions, sim.state().positions); });
    }
    return failures == 0 ? 0 : 2;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
}
