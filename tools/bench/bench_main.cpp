// cloth_sim_bench: speed against error, the bandwidth floor, the stability sweep (docs/benchmark.md).
#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "accuracy.h"
#include "cloth_sim/core/solvers/registry.h"
#include "drift.h"
#include "floor.h"
#include "peers.h"
#include "precision.h"
#include "scaling.h"
#include "self_collision_set.h"
#include "speed.h"
#include "stability.h"
#include "threads.h"

int main(int argc, char** argv) {
  using namespace cloth_sim::bench;
  CLI::App app{"cloth_sim benchmark (see docs/benchmark.md)"};
  app.require_subcommand(1);
  std::string source_dir = CLOTH_SIM_SOURCE_DIR;

  SpeedOptions speed;
  speed.out_dir = source_dir + "/bench/results";
  speed.cache_dir = source_dir + "/bench/cache";
  CLI::App* speed_cmd = app.add_subcommand("speed", "speed against error of every solver");
  speed_cmd->add_option("--out", speed.out_dir, "output directory")->capture_default_str();
  speed_cmd->add_option("--cache", speed.cache_dir, "Newton reference cache ('' = none)")
      ->capture_default_str();
  speed_cmd->add_option("--scenes", speed.scenes, "scenes")->delimiter(',')->capture_default_str()
      ->check(CLI::IsMember({"hanging", "drape"}));
  speed_cmd->add_option("--grids", speed.grids, "grid sizes (rows = cols)")->delimiter(',')
      ->capture_default_str()->check(CLI::Range(4, 400));
  // '@p' sets the first setting of each solver that has settings of its own.
  std::string firsts;
  for (const cloth_sim::SolverEntry& entry : cloth_sim::solverRegistry()) {
    if (!entry.params.empty()) {
      firsts += (firsts.empty() ? "" : ", ") + std::string(entry.params.front()->name);
    }
  }
  speed_cmd->add_option("--solvers", speed.solvers,
                        "solver labels (default: all); '@p' after a label sets the first "
                        "setting of the solver's own: " + firsts)
      ->delimiter(',')
      ->check(CLI::Validator(
          [](std::string& label) {
            const std::string base = label.substr(0, label.find('@'));
            for (const std::string& known : solverLabels())
              if (known == base) return std::string();
            return "unknown solver label '" + base + "'";
          },
          "LABEL[@param]"));
  speed_cmd->add_option("--iterations", speed.iterations, "iteration counts")->delimiter(',')
      ->capture_default_str()->check(CLI::Range(1, 100000));
  speed_cmd->add_option("--duration", speed.duration, "simulated s per timed run")
      ->capture_default_str()->check(CLI::PositiveNumber);
  speed_cmd->add_option("--samples", speed.samples, "error samples per case")
      ->capture_default_str()->check(CLI::Range(1, 100));
  speed_cmd->add_option("--budget", speed.budget, "wall s per timed run (after min steps)")
      ->capture_default_str()->check(CLI::PositiveNumber);
  speed_cmd->add_option("--trace-iterations", speed.trace_iterations,
                        "cap of the per-iteration error traces")
      ->capture_default_str()->check(CLI::Range(1, 1000000));
  bool no_paper = false;
  speed_cmd->add_flag("--no-paper", no_paper, "skip the paper's 81 x 81 cloth");

  StabilityOptions stability;
  stability.out_dir = source_dir + "/bench/results";
  CLI::App* stab_cmd = app.add_subcommand("stability", "stability sweep over stiffness, time step, hard cases");
  stab_cmd->add_option("--out", stability.out_dir, "output directory")->capture_default_str();
  stab_cmd->add_option("--grid", stability.grid, "particles per side")->capture_default_str()
      ->check(CLI::Range(3, 200));
  stab_cmd->add_option("--solvers", stability.solvers,
                       "solvers, <solver>/bdf2 or <solver>/implicit_midpoint for those integrators")
      ->delimiter(',')->capture_default_str()->check(CLI::IsMember(stabilitySolverChoices()));
  stab_cmd->add_option("--stiffness", stability.stiffness, "structural stiffness values, N/m")
      ->delimiter(',')->check(CLI::PositiveNumber);
  stab_cmd->add_option("--dt", stability.time_steps, "time steps, s")->delimiter(',')
      ->check(CLI::PositiveNumber);
  stab_cmd->add_option("--iterations", stability.iterations, "iterations per step")
      ->capture_default_str()->check(CLI::Range(1, 100000));
  stab_cmd->add_option("--duration", stability.duration, "simulated s per cell")
      ->capture_default_str()->check(CLI::PositiveNumber);
  stab_cmd->add_option("--damping", stability.damping, "damping, 1/s")->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  std::vector<std::string> scenario_names;
  stab_cmd->add_option("--scenarios", scenario_names, "release, teleport, sphere")->delimiter(',')
      ->check(CLI::IsMember({"release", "teleport", "sphere"}));

  FloorOptions floor_options;
  floor_options.out_dir = source_dir + "/bench/results";
  CLI::App* floor_cmd = app.add_subcommand("floor", "bandwidth floor and per-iteration cost, paper cloth");
  floor_cmd->add_option("--out", floor_options.out_dir, "output directory")->capture_default_str();
  floor_cmd->add_option("--steps", floor_options.steps, "steps per timed run")
      ->capture_default_str()->check(CLI::Range(2, 100000));
  floor_cmd->add_option("--rounds", floor_options.rounds, "interleaved rounds")
      ->capture_default_str()->check(CLI::Range(1, 1000));

  ScalingOptions scaling;
  scaling.out_dir = source_dir + "/bench/results";
  CLI::App* scaling_cmd =
      app.add_subcommand("scaling", "cost against sphere count and against cloth size on mesh obstacles");
  scaling_cmd->add_option("--out", scaling.out_dir, "output directory")->capture_default_str();
  scaling_cmd->add_option("--duration", scaling.duration, "simulated s per case")
      ->capture_default_str()->check(CLI::PositiveNumber);
  scaling_cmd->add_option("--spheres", scaling.sphere_counts, "sphere counts")->delimiter(',')
      ->capture_default_str()->check(CLI::Range(0, 10000));
  scaling_cmd->add_option("--grids", scaling.obstacle_grids, "cloth sizes over the obstacles")
      ->delimiter(',')->capture_default_str()->check(CLI::Range(4, 400));

  ThreadsOptions threads;
  threads.out_dir = source_dir + "/bench/results";
  CLI::App* threads_cmd =
      app.add_subcommand("threads", "ms per kernel and per frame at each thread count and grid");
  threads_cmd->add_option("--out", threads.out_dir, "output directory")->capture_default_str();
  threads_cmd->add_option("--grids", threads.grids, "grid sizes (rows = cols)")->delimiter(',')
      ->capture_default_str()->check(CLI::Range(4, 1000));
  threads_cmd->add_option("--threads", threads.threads, "thread counts")->delimiter(',')
      ->capture_default_str()->check(CLI::Range(1, 1024));
  threads_cmd->add_option("--solver", threads.solver, "local/global family solver")
      ->capture_default_str()->check(CLI::IsMember({"local_global", "chebyshev", "anderson"}));
  threads_cmd->add_option("--iterations", threads.iterations, "iterations per step")
      ->capture_default_str()->check(CLI::Range(1, 100000));
  threads_cmd->add_option("--linear-solver", threads.linear_solver, "fused or fused_float")
      ->capture_default_str()->check(CLI::IsMember({"fused", "fused_float"}));
  threads_cmd->add_option("--repeats", threads.repeats, "timed calls per kernel")
      ->capture_default_str()->check(CLI::Range(1, 100000));
  threads_cmd->add_option("--frames", threads.frames, "timed frames per thread count")
      ->capture_default_str()->check(CLI::Range(1, 100000));

  PrecisionOptions precision;
  precision.out_dir = source_dir + "/bench/results";
  CLI::App* precision_cmd = app.add_subcommand(
      "precision", "the float factor against the double one: speed and the fixed point reached");
  precision_cmd->add_option("--out", precision.out_dir, "output directory")->capture_default_str();
  precision_cmd->add_option("--grids", precision.grids, "grid sizes (rows = cols)")->delimiter(',')
      ->capture_default_str()->check(CLI::Range(4, 1000));
  precision_cmd->add_option("--threads", precision.threads, "thread counts")->delimiter(',')
      ->capture_default_str()->check(CLI::Range(1, 1024));
  precision_cmd->add_option("--repeats", precision.repeats, "timed calls per kernel")
      ->capture_default_str()->check(CLI::Range(1, 100000));
  precision_cmd->add_option("--frames", precision.frames, "frames of the compared trajectories")
      ->capture_default_str()->check(CLI::Range(1, 100000));

  AccuracyOptions accuracy;
  accuracy.out_dir = source_dir + "/bench/results";
  accuracy.cache_dir = source_dir + "/bench/cache";
  CLI::App* accuracy_cmd = app.add_subcommand(
      "accuracy", "error against the true motion (tiny-step reference) against ms per frame");
  accuracy_cmd->add_option("--out", accuracy.out_dir, "output directory")->capture_default_str();
  accuracy_cmd->add_option("--cache", accuracy.cache_dir, "reference cache ('' = none)")
      ->capture_default_str();
  accuracy_cmd->add_option("--scenes", accuracy.scenes, "scenes")->delimiter(',')
      ->capture_default_str()
      ->check(CLI::IsMember({"hanging", "drape", "trampoline", "gravity_well", "tablecloth",
                              "peer_cloth", "flag", "ball_drop", "curtain", "table_edge",
                              "stiff_flag", "soft_flag"}));
  accuracy_cmd->add_option("--error-tolerances", accuracy.error_tolerances,
                           "error-controlled configurations: tolerances, m per frame")
      ->delimiter(',')->capture_default_str()->check(CLI::Range(1e-9, 1.0));
  bool no_error_control = false;
  accuracy_cmd->add_flag("--no-error-control", no_error_control,
                         "no error-controlled configurations (as an empty --error-tolerances)");
  accuracy_cmd->add_flag("!--no-default", accuracy.scene_default,
                         "leave out the scene format's default (error control, BDF2)");
  accuracy_cmd->add_option("--default-integrator", accuracy.default_integrator,
                           "run the default with this integrator instead of the format's")
      ->check(CLI::IsMember(cloth_sim::integratorNames()));
  accuracy_cmd->add_flag("--default-only", accuracy.default_only,
                         "run the scene format's default only (no sweep)");
  accuracy_cmd->add_option("--local-error-frames", accuracy.local_error_frames,
                           "error-controlled runs: frames whose local error is measured (0 = none)")
      ->capture_default_str()->check(CLI::Range(0, 1000));
  accuracy_cmd->add_option("--error-control-solvers", accuracy.error_control_solvers,
                           "solvers run error-controlled")
      ->delimiter(',')->capture_default_str()->check(CLI::IsMember(cloth_sim::solverNames()));
  accuracy_cmd->add_option("--grids", accuracy.grids, "grid sizes (rows = cols)")->delimiter(',')
      ->capture_default_str()->check(CLI::Range(4, 400));
  accuracy_cmd->add_option("--solvers", accuracy.solvers, "solvers")->delimiter(',')
      ->capture_default_str()->check(CLI::IsMember(cloth_sim::solverNames()));
  accuracy_cmd->add_option("--integrators", accuracy.integrators,
                           "integrators, each configuration runs with each")
      ->delimiter(',')
      ->check(CLI::IsMember(cloth_sim::integratorNames()))
      ->capture_default_str();
  accuracy_cmd->add_option("--substeps", accuracy.substeps, "substeps per frame")->delimiter(',')
      ->capture_default_str()->check(CLI::Range(1, 1000));
  accuracy_cmd->add_option("--xpbd-substeps", accuracy.xpbd_substeps,
                           "substeps per frame of xpbd (1 iteration each)")
      ->delimiter(',')->capture_default_str()->check(CLI::Range(1, 100000));
  accuracy_cmd->add_option("--iterations", accuracy.iterations, "iterations per substep")
      ->delimiter(',')->capture_default_str()->check(CLI::Range(1, 100000));
  accuracy_cmd->add_option("--newton-max-grid", accuracy.newton_max_grid,
                           "converged Newton rows up to this grid (0 = none)")
      ->capture_default_str()->check(CLI::Range(0, 400));
  accuracy_cmd->add_option("--times", accuracy.times, "sample times, s")->delimiter(',')
      ->capture_default_str()->check(CLI::PositiveNumber);
  accuracy_cmd->add_option("--reference", accuracy.reference, "reference integrator")
      ->capture_default_str()->check(CLI::IsMember({"auto", "bdf2", "implicit", "verlet"}));
  accuracy_cmd->add_option("--reference-substeps", accuracy.reference_substeps,
                           "reference: h = frame / (2 x this); its error from h = frame / this")
      ->capture_default_str()->check(CLI::Range(1, 10000));
  std::string warm;
  using cloth_sim::SolverCapabilities;
  for (const std::string& name : cloth_sim::solverNamesWith(&SolverCapabilities::warm_start)) {
    warm += (warm.empty() ? "" : ", ") + name;
  }
  accuracy_cmd->add_flag("--warm-start", accuracy.warm_start,
                         warm + ": warm-started steps (label +warm)");
  accuracy_cmd->add_option("--max-frame-ms", accuracy.max_frame_ms,
                           "stop a configuration slower than this per frame (never the scene's default)")
      ->capture_default_str()->check(CLI::PositiveNumber);

  PeersOptions peers;
  peers.out_dir = source_dir + "/bench/results/bullet";
  peers.cache_dir = source_dir + "/bench/cache";
  const std::string bullet = bulletBuild();
  CLI::App* peers_cmd = app.add_subcommand(
      "peers", "Bullet's implicit deformable solver on the accuracy scenes, error against the same "
               "true motion against ms per frame (" +
                   (bullet.empty() ? std::string("Bullet is absent from this build") : bullet) + ")");
  peers_cmd->add_option("--out", peers.out_dir, "output directory")->capture_default_str();
  peers_cmd->add_option("--cache", peers.cache_dir, "reference cache ('' = none)")
      ->capture_default_str();
  peers_cmd->add_option("--scenes", peers.scenes, "scenes (no colliders)")->delimiter(',')
      ->capture_default_str()
      ->check(CLI::IsMember({"hanging", "peer_cloth", "flag", "stiff_flag", "soft_flag"}));
  peers_cmd->add_option("--grids", peers.grids, "grid sizes (rows = cols)")->delimiter(',')
      ->capture_default_str()->check(CLI::Range(4, 400));
  peers_cmd->add_option("--substeps", peers.substeps, "Bullet steps per frame")->delimiter(',')
      ->capture_default_str()->check(CLI::Range(1, 10000));
  peers_cmd->add_option("--newton-iterations", peers.newton_iterations,
                        "Newton iterations per step (0 = Bullet's default)")
      ->delimiter(',')->capture_default_str()->check(CLI::Range(0, 10000));
  peers_cmd->add_option("--newton-tolerance", peers.newton_tolerance,
                        "Newton's residual norm test, kg m/s (0 = Bullet's default)")
      ->capture_default_str()->check(CLI::NonNegativeNumber);
  peers_cmd->add_option("--krylov-iterations", peers.krylov_iterations,
                        "cap of each linear solve (0 = Bullet's default)")
      ->capture_default_str()->check(CLI::Range(0, 1000000));
  peers_cmd->add_flag("--line-search", peers.line_search,
                      "Newton with Bullet's line search (label +ls)");
  peers_cmd->add_flag("--clamped-hessian", peers.clamped_hessian,
                      "diagnostic: the spring Hessian clamped positive semi-definite (label +psd)");
  peers_cmd->add_flag("!--lagrange", peers.projection,
                      "Bullet's Lagrange multiplier mode (the world's default) instead of its "
                      "projection mode (its examples' with the implicit solver)");
  peers_cmd->add_option("--times", peers.times, "sample times, s")->delimiter(',')
      ->capture_default_str()->check(CLI::PositiveNumber);
  peers_cmd->add_option("--reference", peers.reference, "reference integrator (as accuracy's)")
      ->capture_default_str()->check(CLI::IsMember({"auto", "implicit", "verlet"}));
  peers_cmd->add_option("--reference-substeps", peers.reference_substeps,
                        "as accuracy's --reference-substeps")
      ->capture_default_str()->check(CLI::Range(1, 10000));
  peers_cmd->add_option("--max-frame-ms", peers.max_frame_ms,
                        "stop a configuration slower than this per frame (CPU)")
      ->capture_default_str()->check(CLI::PositiveNumber);

  DriftOptions drift;
  drift.out_dir = source_dir + "/bench/results";
  CLI::App* drift_cmd = app.add_subcommand(
      "drift", "energy of an undamped scene over a long run, per integrator");
  drift_cmd->add_option("--out", drift.out_dir, "output directory")->capture_default_str();
  drift_cmd->add_option("--scene", drift.scene, "scene")->capture_default_str();
  drift_cmd->add_option("--grid", drift.grid, "particles per side (0 = the scene's)")
      ->capture_default_str()->check(CLI::Range(0, 400));
  drift_cmd->add_option("--duration", drift.duration, "simulated s")
      ->capture_default_str()->check(CLI::PositiveNumber);
  drift_cmd->add_option("--configs", drift.configs,
                        "solver[/integrator]:substeps|scene|verlet:iterations|scene")
      ->delimiter(',')->capture_default_str();

  SelfCollisionSetOptions self_set;
  self_set.out_dir = source_dir + "/bench/results";
  CLI::App* self_set_cmd = app.add_subcommand(
      "self_collision_set", "the randomized self-contact set at 16 to 128 particles a side");
  self_set_cmd->add_option("--out", self_set.out_dir, "output directory")->capture_default_str();
  self_set_cmd->add_option("--seeds", self_set.seeds, "cases (seeds from --first-seed on)")
      ->capture_default_str()->check(CLI::Range(1, 1000));
  self_set_cmd->add_option("--first-seed", self_set.first_seed, "the first case's seed")
      ->capture_default_str();
  self_set_cmd->add_option("--max-resolution", self_set.max_resolution,
                           "particles along the longer side at most")
      ->capture_default_str()->check(CLI::Range(16, 400));
  self_set_cmd->add_option("--duration", self_set.seconds, "simulated s per case")
      ->capture_default_str()->check(CLI::PositiveNumber);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 1;
  }
  try {
    speed.scenes_dir = source_dir + "/config/scenes";
    floor_options.scenes_dir = speed.scenes_dir;
    scaling.scenes_dir = speed.scenes_dir;
    scaling.meshes_dir = source_dir + "/config/meshes";
    accuracy.scenes_dir = speed.scenes_dir;
    accuracy.untuned_dir = source_dir + "/bench/scenes";
    if (*floor_cmd) runFloor(floor_options);
    if (no_error_control) accuracy.error_tolerances.clear();
    if (*accuracy_cmd) runAccuracy(accuracy);
    peers.scenes_dir = speed.scenes_dir;
    peers.untuned_dir = accuracy.untuned_dir;
    if (*peers_cmd) runPeers(peers);
    drift.scenes_dir = speed.scenes_dir;
    if (*drift_cmd) runDrift(drift);
    if (*scaling_cmd) runScaling(scaling);
    if (*self_set_cmd && runSelfCollisionSet(self_set) != 0) return 2;
    threads.scenes_dir = speed.scenes_dir;
    if (*threads_cmd) runThreads(threads);
    precision.scenes_dir = speed.scenes_dir;
    if (*precision_cmd) runPrecision(precision);
    if (*speed_cmd) {
      speed.paper = !no_paper;
      runSpeed(speed);
    }
    if (*stab_cmd) {
      if (!scenario_names.empty()) {
        stability.scenarios.clear();
        for (const std::string& n : scenario_names) {
          for (Scenario s : {Scenario::kRelease, Scenario::kTeleport, Scenario::kSphere}) {
            if (n == scenarioName(s)) stability.scenarios.push_back(s);
          }
        }
      }
      runStability(stability);
    }
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
