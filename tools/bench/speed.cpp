#include "speed.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <set>

#include "cases.h"
#include "cloth_sim/core/solvers/implicit_euler_problem.h"
#include "cloth_sim/core/solvers/local_global/lbfgs_solver.h"
#include "cloth_sim/core/solvers/local_global/local_global_solver.h"
#include "cloth_sim/core/solvers/newton_solver.h"
#include "cloth_sim/core/solvers/registry.h"
#include "reference.h"
#include "stats.h"

namespace cloth_sim::bench {
namespace {

struct Config {
  std::string label, solver;
  LinearSolver linear = LinearSolver::kFused;
  bool warm = false;      ///< SolverSettings::warm_start
  bool iterative = true;  ///< false: no iterations to set (explicit), one row at "iterations" 1
  /// After '@': the first setting of the solver's own (its registry entry's params:
  /// chebyshev's rho, anderson's or lbfgs's window) and its value; none when null.
  const SolverParam* param = nullptr;
  double param_value = 0.0;
};

/// Settings @p s with the '@' parameter of @p c applied.
SolverSettings withParam(SolverSettings s, const Config& c) {
  if (c.param != nullptr) s.params.set(*c.param, c.param_value);
  return s;
}

/// "solver[:linear][+warm][@param]", param: the first setting of the solver's own.
Config configOf(const std::string& label) {
  Config c{label, label};
  const auto at = c.solver.find('@');
  double param_value = 0.0;
  if (at != std::string::npos) {
    param_value = std::stod(c.solver.substr(at + 1));
    c.solver = c.solver.substr(0, at);
  }
  const auto plus = c.solver.find('+');
  if (plus != std::string::npos) {
    c.warm = c.solver.substr(plus + 1) == "warm";
    c.solver = c.solver.substr(0, plus);
  }
  const auto colon = c.solver.find(':');
  if (colon != std::string::npos) {
    c.linear = linearSolverFromName(c.solver.substr(colon + 1));
    c.solver = c.solver.substr(0, colon);
  }
  const SolverEntry& entry = solverEntry(c.solver);
  c.iterative = entry.capabilities.iterations;
  if (param_value > 0.0 && !entry.params.empty()) {
    c.param = entry.params.front();
    c.param_value = param_value;
  }
  return c;
}

/// One timed run along the solver's own trajectory, from rest.
struct TimedRun {
  std::vector<double> wall_ms, solve_ms;  ///< steps 2.. (step 1 factors and calibrates)
  double setup_ms = 0.0;                  ///< step 1
  double max_strain = 0.0, energy_end = 0.0, energy_max = 0.0;
  int steps = 0, failures = 0;
};

TimedRun timeRun(const SceneConfig& config, const SpeedOptions& o) {
  Simulation sim = makeSimulation(config);
  const int steps = std::max(2, static_cast<int>(o.duration / sim.substepTime() + 0.5));
  TimedRun run;
  run.energy_max = sim.totalEnergy();
  const double start = now();
  for (int k = 1; k <= steps; ++k) {
    const StepReport r = sim.step();
    if (k == 1) run.setup_ms = 1e3 * r.wall_time;
    else {
      run.wall_ms.push_back(1e3 * r.wall_time);
      run.solve_ms.push_back(1e3 * r.solve_time);
    }
    run.steps = k;
    run.failures += r.status != StepStatus::kOk;
    run.max_strain = std::max(run.max_strain, r.max_strain);
    run.energy_end = sim.totalEnergy();
    run.energy_max = std::max(run.energy_max, run.energy_end);
    if (k > o.min_steps && now() - start > o.budget) break;
  }
  return run;
}

struct Sample {
  int step = 0;
  State previous;  ///< the state one step before: a warm-started solver steps from it first
  State state;
  Reference ref;
};

/// Error of one step from each sample.
void measureErrors(const Config& c, int iterations, const Model& model, const PinSet& pins,
                   double h, const std::vector<Sample>& samples,
                   std::vector<double>& e_g, std::vector<double>& e_x) {
  std::unique_ptr<Solver> solver = makeSolver(c.solver);
  SolverSettings settings;
  settings.max_iterations = iterations;
  settings.linear_solver = c.linear;
  settings.warm_start = c.warm;
  settings = withParam(settings, c);
  const SolverInput input{model, pins, h, 1};
  for (const Sample& s : samples) {
    // The step before the sample first, as in a run: it factors and, with warm start, leaves
    // the previous correction. Then the measured step, from the common state.
    State before = s.previous;
    solver->step(input, settings, before);
    State next = s.state;
    solver->step(input, settings, next);
    const ImplicitStepProblem problem = ImplicitStepProblem::build(model, pins, s.state, h);
    e_g.push_back(s.ref.objectiveError(problem.objective(next.positions)));
    e_x.push_back(s.ref.positionError(next.positions));
  }
}

/// Newton's errors after each iteration count: one run per sample, continued from the previous
/// count's iterate (minimize is restarted, so the exact-Hessian switch is re-armed).
std::map<int, std::pair<std::vector<double>, std::vector<double>>> newtonErrors(
    const std::vector<int>& counts, const Model& model, const PinSet& pins, double h,
    const std::vector<Sample>& samples) {
  std::map<int, std::pair<std::vector<double>, std::vector<double>>> out;
  std::vector<int> sorted = counts;
  std::sort(sorted.begin(), sorted.end());
  NewtonSolver newton;
  const SolverInput input{model, pins, h, 1};
  for (const Sample& s : samples) {
    const ImplicitStepProblem problem = ImplicitStepProblem::build(model, pins, s.state, h);
    Points x = problem.inertial;
    int done = 0;
    for (int k : sorted) {
      SolverSettings settings;
      settings.max_iterations = k - done;
      newton.minimize(input, settings, problem, x);
      done = k;
      out[k].first.push_back(s.ref.objectiveError(problem.objective(x)));
      out[k].second.push_back(s.ref.positionError(x));
    }
  }
  return out;
}

/// Per-iteration errors of local/global, chebyshev, anderson or lbfgs, up to trace_iterations or both
/// < 1e-4.
void traceErrors(const std::string& case_name, const Config& c, const Model& model,
                 const PinSet& pins, double h, const std::vector<Sample>& samples,
                 int cap, std::ofstream& out) {
  const std::unique_ptr<Solver> owned = makeSolver(c.solver);
  auto* solver = dynamic_cast<LocalGlobalFamily*>(owned.get());
  if (solver == nullptr || c.linear != LinearSolver::kFused) return;  // no iterate observer
  SolverSettings settings;
  settings.linear_solver = c.linear;
  settings.warm_start = c.warm;
  settings = withParam(settings, c);
  const SolverInput input{model, pins, h, 1};
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const Sample& s = samples[i];
    solver->setIterateObserver({});
    settings.max_iterations = 10;
    State before = s.previous;
    solver->step(input, settings, before);
    settings.max_iterations = cap;
    const ImplicitStepProblem problem = ImplicitStepProblem::build(model, pins, s.state, h);
    int next_logged = 1;
    solver->setIterateObserver([&](int k, const Points& x) {
      const double eg = s.ref.objectiveError(problem.objective(x));
      const double ex = s.ref.positionError(x);
      const bool done = eg < 1e-4 && ex < 1e-4;
      if (k >= next_logged || done || k == cap) {
        out << case_name << ',' << c.label << ',' << i << ',' << k << ',' << eg << ',' << ex << '\n';
        next_logged = std::max(k + 1, static_cast<int>(k * 1.05));
      }
      return !done;
    });
    State next = s.state;
    solver->step(input, settings, next);
  }
}

/// @p config with the solver, iterations, linear solver, warm start and '@' parameter of @p c.
SceneConfig withSolver(const SceneConfig& config, const Config& c, int iterations) {
  SceneOverrides overrides;
  overrides.solver = c.solver;
  overrides.iterations = iterations;
  overrides.linear_solver = c.linear;
  overrides.warm_start = c.warm;
  if (c.param != nullptr) overrides.params.emplace_back(c.param, c.param_value);
  return applyOverrides(config, overrides);
}

void writeRow(std::ofstream& out, const BenchCase& bc, const Model& model, double h,
              const Config& c, int iterations, const TimedRun& run, const std::vector<double>& e_g,
              const std::vector<double>& e_x, bool refs_converged) {
  out << bc.name << ',' << bc.scene << ',' << bc.grid << ',' << (bc.paper ? "paper" : "scene")
      << ',' << model.particleCount() << ',' << model.springs.size() << ',' << h
      << ',' << c.label << ',' << iterations << ',' << run.steps << ',' << median(run.wall_ms)
      << ',' << quantile(run.wall_ms, 0.1) << ',' << quantile(run.wall_ms, 0.9) << ','
      << median(run.solve_ms) << ',' << run.setup_ms << ',' << median(e_g) << ',' << maxOf(e_g)
      << ',' << median(e_x) << ',' << maxOf(e_x) << ',' << run.max_strain << ','
      << run.energy_end << ',' << run.energy_max << ',' << run.failures << ','
      << (refs_converged ? 1 : 0) << '\n';
  out.flush();
}

}  // namespace

std::vector<std::string> solverLabels() {
  // Every solver of the registry; warm-started too where that applies; the default solver
  // with each other linear solver.
  const std::string default_solver = SimulationOptions{}.solver;
  std::vector<std::string> labels;
  for (const SolverEntry& entry : solverRegistry()) {
    labels.emplace_back(entry.name);
    if (entry.name != default_solver) continue;
    for (LinearSolver linear : kLinearSolvers) {
      if (linear != SolverSettings{}.linear_solver) {
        labels.push_back(default_solver + ":" + linearSolverName(linear));
      }
    }
  }
  for (const SolverEntry& entry : solverRegistry()) {
    if (entry.capabilities.warm_start) labels.push_back(std::string(entry.name) + "+warm");
  }
  return labels;
}

void runSpeed(const SpeedOptions& o) {
  std::filesystem::create_directories(o.out_dir);
  std::ofstream speed(o.out_dir + "/speed.csv"), traces(o.out_dir + "/traces.csv"),
      refs(o.out_dir + "/references.csv"), cases(o.out_dir + "/cases.csv");
  speed << "case,scene,grid,topology,particles,springs,h,solver,iterations,steps,ms_median,ms_p10,"
           "ms_p90,solve_ms_median,setup_ms,err_g_median,err_g_max,err_x_median,err_x_max,"
           "max_strain,energy_end,energy_max,failures,refs_converged\n";
  traces << "case,solver,sample,k,err_g,err_x\n";
  refs << "case,sample,step,time,converged,newton_iterations,grad_ratio,seconds\n";
  cases << "case,particles,springs,free,factor_nonzeros,factor_solve_bytes,h\n";

  std::vector<BenchCase> all;
  for (int grid : o.grids) {
    for (const std::string& scene : o.scenes) all.push_back(makeCase(o.scenes_dir, scene, grid));
    if (o.paper && grid == 81) all.push_back(makePaperCase(o.scenes_dir));
  }
  const std::vector<std::string> labels = o.solvers.empty() ? solverLabels() : o.solvers;

  for (const BenchCase& bc : all) {
    // Common start states: local_global (its factor is reported below), sampled along its
    // trajectory.
    Simulation sim = makeSimulation(withSolver(bc.config, "local_global", 10, LinearSolver::kFused));
    const Model model = sim.model();
    const double h = sim.substepTime();
    const PinSet pins = sim.pins();
    const int steps = std::max(1, static_cast<int>(o.duration / h + 0.5));
    std::vector<Sample> samples;
    for (int k = 1; k <= steps; ++k) {
      const State previous = sim.state();
      sim.step();
      if (static_cast<int>(samples.size()) < o.samples &&
          k == (static_cast<int>(samples.size()) + 1) * steps / o.samples) {
        samples.push_back({k, previous, sim.state(), {}});
      }
    }
    bool all_converged = true;
    for (std::size_t i = 0; i < samples.size(); ++i) {
      Sample& s = samples[i];
      s.ref = computeReference(model, pins, s.state, h, o.cache_dir);
      all_converged = all_converged && s.ref.converged;
      refs << bc.name << ',' << i << ',' << s.step << ',' << s.state.time << ','
           << (s.ref.converged ? 1 : 0) << ',' << s.ref.newton_iterations << ','
           << s.ref.grad_ratio << ',' << s.ref.seconds << '\n';
      std::fprintf(stderr, "[bench] %s: reference %zu (t = %.2f s): %s, %d Newton iterations, "
                   "|grad|/|grad0| %.1e, %.1f s\n", bc.name.c_str(), i, s.state.time,
                   s.ref.converged ? "converged" : "NOT converged", s.ref.newton_iterations,
                   s.ref.grad_ratio, s.ref.seconds);
    }
    refs.flush();
    {
      // The sampling run's local/global (fused, default settings) holds the factor.
      const auto& factored = static_cast<const LocalGlobalSolver&>(sim.solver());
      cases << bc.name << ',' << model.particleCount() << ',' << model.springs.size() << ','
            << factored.system().size() << ',' << factored.system().factorNonZeros() << ','
            << factored.system().supernodal().solveBytes() << ',' << h << '\n';
      cases.flush();
    }

    for (const std::string& label : labels) {
      const Config c = configOf(label);
      const std::vector<int> counts = c.iterative ? o.iterations : std::vector<int>{1};
      const bool is_newton = c.solver == "newton";
      const auto newton = is_newton ? newtonErrors(counts, model, pins, h, samples)
                                    : decltype(newtonErrors(counts, model, pins, h, samples)){};
      for (int iterations : counts) {
        const double t0 = now();
        const TimedRun run = timeRun(withSolver(bc.config, c, iterations), o);
        std::vector<double> e_g = is_newton ? newton.at(iterations).first : std::vector<double>();
        std::vector<double> e_x = is_newton ? newton.at(iterations).second : std::vector<double>();
        if (!is_newton) measureErrors(c, iterations, model, pins, h, samples, e_g, e_x);
        writeRow(speed, bc, model, h, c, iterations, run, e_g, e_x, all_converged);
        std::fprintf(stderr, "[bench] %-10s %-22s %3d it: %8.3f ms/step, err_g %.2e err_x %.2e "
                     "(%.1f s)\n", bc.name.c_str(), label.c_str(), iterations, median(run.wall_ms),
                     median(e_g), median(e_x), now() - t0);
      }
      traceErrors(bc.name, c, model, pins, h, samples, o.trace_iterations, traces);
      traces.flush();
    }
  }
}

}  // namespace cloth_sim::bench
