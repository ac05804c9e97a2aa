#include "threads.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <stdexcept>

#include "cases.h"
#include "cloth_sim/core/solvers/local_global/anderson_acceleration.h"
#include "cloth_sim/core/solvers/local_global/local_global_problem.h"
#include "stats.h"

namespace cloth_sim::bench {
namespace {

/// The timed configuration at @p threads threads.
SceneConfig configAt(const BenchCase& c, const ThreadsOptions& o, int threads) {
  SceneOverrides overrides;
  overrides.solver = o.solver;
  overrides.iterations = o.iterations;
  overrides.integrator = Integrator::kBdf2;
  overrides.linear_solver = linearSolverFromName(o.linear_solver);
  overrides.threads = threads;
  return applyOverrides(c.config, overrides);
}

}  // namespace

void runThreads(const ThreadsOptions& o) {
  std::string path;
  std::ofstream csv = openCsv(o.out_dir, "threads.csv",
                              "grid,particles,springs,factor_nonzeros,solve_tasks,kernel,threads,"
                              "ms_median,ms_min,samples",
                              path);
  for (int grid : o.grids) {
    const BenchCase c = makeCase(o.scenes_dir, "hanging", grid);
    // One simulation per thread count, all at the same moving state (the same bits).
    std::vector<std::unique_ptr<Simulation>> sims;
    for (int t : o.threads) {
      sims.push_back(std::make_unique<Simulation>(makeSimulation(configAt(c, o, t))));
      while (sims.back()->state().time < 0.25) sims.back()->step();
    }
    const Simulation& sim = *sims.front();
    const SolverInput input{sim.model(), sim.pins(), sim.substepTime(), 1};
    const State state = sim.state();
    std::vector<SolverSettings> settings;
    for (int t : o.threads) {
      settings.push_back(sim.solverSettings());
      settings.back().threads = t;
    }
    LocalGlobalProblem problem;
    problem.begin(input, settings.front(), state);  // factors (not timed)
    const NodeBuffer x = problem.initialGuess(settings.front());
    NodeBuffer x_hat(x.size()), x_next(x.size()), rhs(x.size(), 0.0), work(x.size());
    problem.iterate(x, x_hat);
    const SupernodalFactor& factor = problem.system().supernodal();
    std::vector<AndersonAcceleration> anderson(o.threads.size());

    // kernel -> threads index -> samples (ms)
    std::map<std::string, std::vector<std::vector<double>>> ms;
    auto record = [&](const std::string& kernel, std::size_t t, double value) {
      auto& per = ms[kernel];
      per.resize(o.threads.size());
      per[t].push_back(value);
    };
    for (int r = 0; r < o.repeats; ++r) {
      for (std::size_t t = 0; t < o.threads.size(); ++t) {
        const int n = o.threads[t];
        record("setup", t, timeMs([&] { problem.begin(input, settings[t], state); }));
        record("local step", t, timeMs([&] { localStep3(problem.springTable(), x.data(), rhs.data(), n); }));
        work = x_hat;
        record("forward solve", t, timeMs([&] { forwardSolve3(factor, work.data(), n); }));
        record("backward solve", t, timeMs([&] { backwardSolve3(factor, work.data(), n); }));
        record("iteration", t, timeMs([&] { problem.iterate(x, x_next); }));
        record("objective", t, timeMs([&] { problem.objectiveAt(x); }));
        if (r == 0) anderson[t].begin(input, settings[t]);
        record("anderson update", t,
               timeMs([&] { anderson[t].extrapolate(x, x_hat, x_next, work); }));
      }
    }
    for (int f = 0; f < o.frames; ++f) {
      for (std::size_t t = 0; t < o.threads.size(); ++t) record("frame", t, 1e3 * sims[t]->step().wall_time);
    }
    for (const auto& [kernel, per] : ms) {
      for (std::size_t t = 0; t < o.threads.size(); ++t) {
        csv << grid << ',' << sim.model().particleCount() << ',' << sim.model().springs.size()
            << ',' << problem.system().factorNonZeros() << ',' << factor.tasks.tasks.size() << ','
            << kernel << ',' << o.threads[t] << ',' << median(per[t]) << ','
            << quantile(per[t], 0.0) << ',' << per[t].size() << '\n';
      }
      std::fprintf(stderr, "[threads] %3d x %-3d %-16s", grid, grid, kernel.c_str());
      for (std::size_t t = 0; t < o.threads.size(); ++t) {
        std::fprintf(stderr, "  %d: %8.3f ms (min %8.3f)", o.threads[t], median(per[t]),
                     quantile(per[t], 0.0));
      }
      if (o.threads.size() >= 2) {
        std::fprintf(stderr, "  speed-up %.2f (min %.2f)", median(per[0]) / median(per.back()),
                     quantile(per[0], 0.0) / quantile(per.back(), 0.0));
      }
      std::fprintf(stderr, "\n");
    }
    csv.flush();
  }
  std::fprintf(stderr, "wrote %s\n", path.c_str());
}

}  // namespace cloth_sim::bench
