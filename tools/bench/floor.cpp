#include "floor.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <vector>

#include "cases.h"
#include "cloth_sim/core/solvers/local_global/local_global_solver.h"
#include "stats.h"

namespace cloth_sim::bench {
namespace {

typedef double Block __attribute__((vector_size(32), aligned(8)));

/// Sums @p count doubles with eight independent vector accumulators: a pure read stream.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("arch=x86-64-v3", "default")))
#endif
double streamSum(const double* data, std::size_t count) {
  Block a[8] = {};
  std::size_t k = 0;
  for (; k + 32 <= count; k += 32) {
    for (int u = 0; u < 8; ++u) a[u] += *reinterpret_cast<const Block*>(data + k + 4 * u);
  }
  Block s = ((a[0] + a[1]) + (a[2] + a[3])) + ((a[4] + a[5]) + (a[6] + a[7]));
  double total = s[0] + s[1] + s[2] + s[3];
  for (; k < count; ++k) total += data[k];
  return total;
}

/// Median read bandwidth (bytes/s) streaming a buffer of @p bytes over and over.
double readBandwidth(std::size_t bytes) {
  std::vector<double, CacheAlignedAllocator<double>> buffer(bytes / sizeof(double), 1.0);
  volatile double sink = 0.0;
  std::vector<double> seconds;
  const int repeats = static_cast<int>(std::max<std::size_t>(20, (4u << 30) / std::max<std::size_t>(bytes, 1)));
  for (int r = 0; r < std::min(repeats, 2000); ++r) {
    const double t0 = now();
    sink = sink + streamSum(buffer.data(), buffer.size());
    seconds.push_back(now() - t0);
  }
  return static_cast<double>(bytes) / median(seconds);
}

struct Timing {
  std::vector<double> ms;  // per step, steps 2..
};

/// Runs @p steps steps of @p config and appends the wall ms of each (after the first) to @p t.
void timeSteps(const SceneConfig& config, int steps, Timing& t) {
  Simulation sim = makeSimulation(config);
  for (int k = 0; k < steps; ++k) {
    const StepReport r = sim.step();
    if (k > 0) t.ms.push_back(1e3 * r.solve_time);
  }
}

}  // namespace

void runFloor(const FloorOptions& o) {
  std::filesystem::create_directories(o.out_dir);
  const BenchCase paper = makePaperCase(o.scenes_dir);
  Simulation probe_sim = makeSimulation(paper.config);
  LocalGlobalSolver probe;
  State state = probe_sim.state();
  probe.step({probe_sim.model(), probe_sim.pins(), probe_sim.substepTime(), 1}, SolverSettings{},
             state);
  const SupernodalFactor& factor = probe.system().supernodal();
  const std::size_t springs = probe.springTable().size();
  const int nodes = probe_sim.model().particleCount();

  // Bytes that must stream from beyond L2 every iteration: the factor (read twice: forward and
  // backward, values, row lists, inverse diagonal) and the spring table. The node
  // vectors (x, rhs, y: 32 bytes per node each) are reused from L2 and counted apart.
  const double factor_bytes = static_cast<double>(factor.solveBytes());
  const double spring_bytes = static_cast<double>(springs) * (2 * sizeof(int) + 3 * sizeof(double));
  const double node_bytes = 10.0 * nodes * kNodeStride * sizeof(double);
  const double stream_bytes = factor_bytes + spring_bytes;
  const double bw_cache = readBandwidth(static_cast<std::size_t>(stream_bytes));
  const double bw_dram = readBandwidth(std::size_t{512} << 20);
  const double floor_cache_ms = 1e3 * stream_bytes / bw_cache;
  const double floor_dram_ms = 1e3 * stream_bytes / bw_dram;

  // Per-iteration cost: steps at 1 and 10 iterations, interleaved rounds, medians.
  struct Variant {
    std::string label, solver;
    LinearSolver linear;
  };
  // local_global with each linear solver, against the 3N x 3N factor it replaced and the
  // acceleration's own cost (chebyshev on the fused kernels).
  std::vector<Variant> variants;
  for (const LinearSolver linear : kLinearSolvers) {
    const std::string name = linearSolverName(linear);
    const std::string how = linear == LinearSolver::kFused ? name : name + " solve";
    variants.push_back({"local_global (" + how + ")", "local_global", linear});
  }
  variants.push_back({"local_global_3n", "local_global_3n", LinearSolver::kEigen});
  variants.push_back({"chebyshev (fused)", "chebyshev", LinearSolver::kFused});
  std::map<std::string, std::map<int, Timing>> timings;
  for (int round = 0; round < o.rounds; ++round) {
    for (const Variant& v : variants) {
      for (int iterations : {1, 10}) {
        timeSteps(withSolver(paper.config, v.solver, iterations, v.linear), o.steps,
                  timings[v.label][iterations]);
      }
    }
    std::fprintf(stderr, "[floor] round %d of %d done\n", round + 1, o.rounds);
  }

  // The kernels alone, on the factor and springs of the paper cloth (realistic data: the rest
  // positions, a right-hand side of the right magnitude).
  NodeBuffer x(static_cast<std::size_t>(kNodeStride) * nodes, 0.0), rhs(x.size(), 0.0), work;
  for (int k = 0; k < nodes; ++k)
    for (int c = 0; c < 3; ++c) x[kNodeStride * k + c] = state.positions(c, k);
  localStep3(probe.springTable(), x.data(), rhs.data());
  std::vector<double> t_local, t_forward, t_backward;
  for (int r = 0; r < 200; ++r) {
    work = rhs;
    double t0 = now();
    localStep3(probe.springTable(), x.data(), work.data());
    t_local.push_back(1e3 * (now() - t0));
    work = rhs;
    t0 = now();
    forwardSolve3(factor, work.data());
    t_forward.push_back(1e3 * (now() - t0));
    t0 = now();
    backwardSolve3(factor, work.data());
    t_backward.push_back(1e3 * (now() - t0));
  }

  std::ofstream floor(o.out_dir + "/floor.csv");
  floor << "quantity,value,unit\n"
        << "particles," << nodes << ",\n"
        << "free particles," << factor.size << ",\n"
        << "springs," << probe_sim.model().springs.size() << ",\n"
        << "factor nonzeros," << probe.system().factorNonZeros() << ",\n"
        << "supernodes," << factor.supernodeCount() << ",\n"
        << "factor bytes per iteration (forward + backward)," << factor_bytes << ",B\n"
        << "spring table bytes per iteration," << spring_bytes << ",B\n"
        << "node vector bytes per iteration (L2-resident)," << node_bytes << ",B\n"
        << "read bandwidth at that working set," << bw_cache / 1e9 << ",GB/s\n"
        << "read bandwidth from DRAM (512 MB)," << bw_dram / 1e9 << ",GB/s\n"
        << "floor per iteration at working-set bandwidth," << floor_cache_ms << ",ms\n"
        << "floor per iteration at DRAM bandwidth," << floor_dram_ms << ",ms\n"
        << "local step alone," << median(t_local) << ",ms\n"
        << "forward solve alone," << median(t_forward) << ",ms\n"
        << "backward solve alone," << median(t_backward) << ",ms\n";
  std::ofstream kernels(o.out_dir + "/kernels.csv");
  kernels << "variant,ms_per_step_10,p10,p90,ms_per_step_1,ms_per_iteration\n";
  std::fprintf(stderr, "[floor] stream %.2f MB/iteration: %.1f GB/s at that size -> %.3f ms; "
               "DRAM %.1f GB/s -> %.3f ms\n", stream_bytes / 1e6, bw_cache / 1e9, floor_cache_ms,
               bw_dram / 1e9, floor_dram_ms);
  for (const Variant& v : variants) {
    auto& t = timings[v.label];
    // (t10 - t1) / 9: the per-step overhead (y, rhs constant, contacts, checks) cancels.
    const double per_iteration = (median(t[10].ms) - median(t[1].ms)) / 9.0;
    kernels << v.label << ',' << median(t[10].ms) << ',' << quantile(t[10].ms, 0.1) << ','
            << quantile(t[10].ms, 0.9) << ',' << median(t[1].ms) << ',' << per_iteration << '\n';
    std::fprintf(stderr, "[floor] %-30s 10 it: %7.3f ms/step (p10 %.3f, p90 %.3f); 1 it: %.3f; "
                 "per iteration: %.3f ms\n", v.label.c_str(), median(t[10].ms), quantile(t[10].ms, 0.1),
                 quantile(t[10].ms, 0.9), median(t[1].ms), per_iteration);
  }
}

}  // namespace cloth_sim::bench
