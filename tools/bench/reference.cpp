#include "reference.h"

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cloth_sim/core/solvers/implicit_euler_problem.h"
#include "cloth_sim/core/solvers/local_global/local_global_solver.h"
#include "cloth_sim/core/solvers/newton_solver.h"
#include "stats.h"

namespace cloth_sim::bench {
namespace {

/// FNV-1a over raw bytes.
struct Hash {
  std::uint64_t h = 1469598103934665603ull;
  void add(const void* data, std::size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t k = 0; k < bytes; ++k) h = (h ^ p[k]) * 1099511628211ull;
  }
  void add(double v) { add(&v, sizeof v); }
  void add(const Points& x) { add(x.data(), sizeof(double) * x.size()); }
};

std::uint64_t keyOf(const Model& model, const PinSet& pins, const State& state, double step) {
  Hash h;
  h.add(state.positions);
  h.add(state.velocities);
  h.add(step);
  h.add(model.damping);
  h.add(model.gravity.data(), sizeof(double) * 3);
  h.add(model.mass.data(), sizeof(double) * model.mass.size());
  h.add(model.springs.first.data(), sizeof(int) * model.springs.size());
  h.add(model.springs.second.data(), sizeof(int) * model.springs.size());
  h.add(model.springs.stiffness.data(), sizeof(double) * model.springs.size());
  h.add(model.springs.rest_length.data(), sizeof(double) * model.springs.size());
  for (const Pin& p : pins.pins()) {
    h.add(&p.vertex, sizeof p.vertex);
    h.add(p.target.data(), sizeof(double) * 3);
    h.add(p.stiffness);
  }
  return h.h;
}

constexpr std::uint32_t kMagic = 0x434c5231;  // "CLR1"
/// A reference counts as converged when Newton's test passed and |grad g| fell by this much.
constexpr double kConvergedGradient = 1e-8;

bool readCache(const std::string& path, Reference& ref) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::uint32_t magic = 0;
  std::int64_t cols = 0;
  std::int32_t converged = 0, iterations = 0;
  in.read(reinterpret_cast<char*>(&magic), sizeof magic);
  in.read(reinterpret_cast<char*>(&cols), sizeof cols);
  in.read(reinterpret_cast<char*>(&converged), sizeof converged);
  in.read(reinterpret_cast<char*>(&iterations), sizeof iterations);
  in.read(reinterpret_cast<char*>(&ref.grad_ratio), sizeof ref.grad_ratio);
  if (!in || magic != kMagic || cols != ref.start.cols()) return false;
  if (!(ref.grad_ratio <= kConvergedGradient)) return false;  // try again: Newton got better
  ref.x_star.resize(3, cols);
  in.read(reinterpret_cast<char*>(ref.x_star.data()), sizeof(double) * ref.x_star.size());
  ref.converged = converged != 0;
  ref.newton_iterations = iterations;
  return static_cast<bool>(in);
}

void writeCache(const std::string& path, const Reference& ref) {
  std::ofstream out(path, std::ios::binary);
  const std::int64_t cols = ref.x_star.cols();
  const std::int32_t converged = ref.converged, iterations = ref.newton_iterations;
  out.write(reinterpret_cast<const char*>(&kMagic), sizeof kMagic);
  out.write(reinterpret_cast<const char*>(&cols), sizeof cols);
  out.write(reinterpret_cast<const char*>(&converged), sizeof converged);
  out.write(reinterpret_cast<const char*>(&iterations), sizeof iterations);
  out.write(reinterpret_cast<const char*>(&ref.grad_ratio), sizeof ref.grad_ratio);
  out.write(reinterpret_cast<const char*>(ref.x_star.data()), sizeof(double) * ref.x_star.size());
}

}  // namespace

Reference computeReference(const Model& model, const PinSet& pins, const State& state, double h,
                           const std::string& cache_dir, int warm_iterations) {
  const ImplicitStepProblem problem = ImplicitStepProblem::build(model, pins, state, h);
  Reference ref;
  ref.start = problem.inertial;
  ref.g_start = problem.objective(ref.start);

  std::string path;
  if (!cache_dir.empty()) {
    std::filesystem::create_directories(cache_dir);
    std::ostringstream name;
    name << cache_dir << "/ref_" << std::hex << keyOf(model, pins, state, h) << ".bin";
    path = name.str();
  }
  if (path.empty() || !readCache(path, ref)) {
    const double t0 = now();
    const SolverInput input{model, pins, h, 1};
    SolverSettings settings;
    settings.max_iterations = warm_iterations;
    ChebyshevSolver warm;
    State guess = state;
    warm.step(input, settings, guess);
    ref.x_star = guess.positions;
    NewtonSolver newton;
    settings.max_iterations = 300;
    settings.tolerance = 1e-12;
    const SolveResult r = newton.minimize(input, settings, problem, ref.x_star);
    ref.converged = r.converged;
    ref.newton_iterations = r.iterations;
    Points grad, grad0;
    problem.gradient(ref.x_star, grad);
    problem.gradient(ref.start, grad0);
    ref.grad_ratio = grad.norm() / grad0.norm();
    ref.converged = ref.converged && ref.grad_ratio <= kConvergedGradient;
    ref.seconds = now() - t0;
    if (!path.empty()) writeCache(path, ref);
  }
  ref.g_star = problem.objective(ref.x_star);
  return ref;
}

}  // namespace cloth_sim::bench
