#include "precision.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <stdexcept>

#include "cases.h"
#include "cloth_sim/core/solvers/local_global/local_global_problem.h"
#include "stats.h"

namespace cloth_sim::bench {
namespace {

/// The positions after @p frames frames of @p config with @p linear, @p iterations per step and
/// @p tolerance; @p iterations_done gets the last frame's iterations.
Points runFrames(const SceneConfig& config, LinearSolver linear, int iterations, double tolerance,
                 int frames, int* iterations_done = nullptr) {
  SceneConfig c = withSolver(config, "anderson", iterations, linear);
  c.options.settings.tolerance = tolerance;
  Simulation sim = makeSimulation(c);
  for (int f = 0; f < frames; ++f) {
    const StepReport report = sim.step();
    if (report.status != StepStatus::kOk) throw std::runtime_error("precision: " + report.message);
    if (iterations_done != nullptr) *iterations_done = report.iterations;
  }
  return sim.state().positions;
}

struct Distance {
  double rms = 0.0, max = 0.0;  ///< m
};

Distance distance(const Points& a, const Points& b) {
  const Eigen::VectorXd d = (a - b).colwise().norm();
  return {std::sqrt(d.squaredNorm() / std::max<Eigen::Index>(d.size(), 1)), d.maxCoeff()};
}

}  // namespace

void runPrecision(const PrecisionOptions& o) {
  std::string path;
  std::ofstream csv = openCsv(o.out_dir, "precision.csv", "grid,particles,quantity,threads,value", path);
  for (int grid : o.grids) {
    const BenchCase c = makeCase(o.scenes_dir, "hanging", grid);
    const SceneConfig config = applyOverrides(c.config, [] {
      SceneOverrides s;
      s.integrator = Integrator::kBdf2;
      return s;
    }());
    Simulation sim = makeSimulation(withSolver(config, "anderson", 10, LinearSolver::kFused));
    while (sim.state().time < 0.25) sim.step();
    const int particles = sim.model().particleCount();
    const double diagonal = std::hypot(c.config.grid.width, c.config.grid.height);
    const SolverInput input{sim.model(), sim.pins(), sim.substepTime(), 1};
    const State state = sim.state();
    const auto row = [&](const std::string& quantity, int threads, double value) {
      csv << grid << ',' << particles << ',' << quantity << ',' << threads << ',' << value << '\n';
    };

    // Speed: the solves and one iteration, double and float, interleaved.
    SolverSettings settings = sim.solverSettings();
    LocalGlobalProblem dbl, flt;
    settings.linear_solver = LinearSolver::kFused;
    dbl.begin(input, settings, state);
    settings.linear_solver = LinearSolver::kFusedFloat;
    flt.begin(input, settings, state);
    const NodeBuffer x = dbl.initialGuess(settings);
    NodeBuffer x_hat(x.size()), next(x.size());
    dbl.iterate(x, x_hat);
    NodeBuffer work(x_hat);
    std::vector<float> work_f(x_hat.begin(), x_hat.end());
    for (int t : o.threads) {
      std::vector<double> ms[4];
      for (int r = 0; r < o.repeats; ++r) {
        ms[0].push_back(timeMs([&] { solveFused3(dbl.system().supernodal(), work.data(), t); }));
        ms[1].push_back(timeMs([&] { solveFused3(flt.system().supernodalFloat(), work_f.data(), t); }));
        settings.threads = t;
        settings.linear_solver = LinearSolver::kFused;
        dbl.begin(input, settings, state);
        ms[2].push_back(timeMs([&] { dbl.iterate(x, next); }));
        settings.linear_solver = LinearSolver::kFusedFloat;
        flt.begin(input, settings, state);
        ms[3].push_back(timeMs([&] { flt.iterate(x, next); }));
      }
      const char* names[4] = {"solve double ms", "solve float ms", "iteration double ms",
                              "iteration float ms"};
      std::fprintf(stderr, "[precision] %3d x %-3d %d thread(s):", grid, grid, t);
      for (int k = 0; k < 4; ++k) {
        row(names[k], t, median(ms[k]));
        std::fprintf(stderr, "  %s %.3f", names[k], median(ms[k]));
      }
      std::fprintf(stderr, "  (solve %.2fx, iteration %.2fx)\n", median(ms[0]) / median(ms[1]),
                   median(ms[2]) / median(ms[3]));
    }

    // The fixed point: one frame converged (relative change 1e-13) with each factor.
    int it_double = 0, it_float = 0;
    const Points fixed_d = runFrames(config, LinearSolver::kFused, 2000, 1e-13, 1, &it_double);
    const Points fixed_f = runFrames(config, LinearSolver::kFusedFloat, 2000, 1e-13, 1, &it_float);
    const Distance fixed = distance(fixed_d, fixed_f);
    // The budget's iterates: one frame and a second of frames at 10 iterations.
    const Distance one = distance(runFrames(config, LinearSolver::kFused, 10, 0.0, 1),
                                  runFrames(config, LinearSolver::kFusedFloat, 10, 0.0, 1));
    const Distance second = distance(runFrames(config, LinearSolver::kFused, 10, 0.0, o.frames),
                                     runFrames(config, LinearSolver::kFusedFloat, 10, 0.0, o.frames));
    // The same for two double backends that differ in round-off only (fused, CHOLMOD's solve):
    // how far rounding alone carries the trajectory apart.
    const Distance baseline = distance(runFrames(config, LinearSolver::kFused, 10, 0.0, o.frames),
                                       runFrames(config, LinearSolver::kCholmod, 10, 0.0, o.frames));
    row("fixed point rms / diagonal", 0, fixed.rms / diagonal);
    row("fixed point max / diagonal", 0, fixed.max / diagonal);
    row("fixed point iterations double", 0, it_double);
    row("fixed point iterations float", 0, it_float);
    row("1 frame of 10 it rms / diagonal", 0, one.rms / diagonal);
    row("frames of 10 it rms / diagonal", 0, second.rms / diagonal);
    row("frames of 10 it max / diagonal", 0, second.max / diagonal);
    row("frames of 10 it rms / diagonal, fused vs cholmod", 0, baseline.rms / diagonal);
    std::fprintf(stderr,
                 "[precision] %3d x %-3d converged frame: rms %.2e max %.2e of the diagonal "
                 "(%d / %d iterations); 1 frame of 10 it: rms %.2e; %d frames: rms %.2e max %.2e "
                 "(fused against cholmod, both double: rms %.2e)\n",
                 grid, grid, fixed.rms / diagonal, fixed.max / diagonal, it_double, it_float,
                 one.rms / diagonal, o.frames, second.rms / diagonal, second.max / diagonal,
                 baseline.rms / diagonal);
    csv.flush();
  }
  std::fprintf(stderr, "wrote %s\n", path.c_str());
}

}  // namespace cloth_sim::bench
