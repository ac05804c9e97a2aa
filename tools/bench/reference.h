// Converged implicit Euler solutions (Newton) for the benchmark's error measures, cached on disk.
#pragma once

#include <string>

#include "cloth_sim/core/model/model.h"
#include "cloth_sim/core/model/pins.h"

namespace cloth_sim::bench {

/// x* = argmin g of one implicit Euler step (docs/method.md), and how well it is converged.
struct Reference {
  Points x_star;             ///< m
  double g_star = 0.0;       ///< g(x*), kg m^2
  double g_start = 0.0;      ///< g(y), the common initial guess of the iterative solvers
  Points start;              ///< y, m
  bool converged = false;    ///< Newton's stopping test passed and |grad g| fell by 1e-8
  int newton_iterations = 0;
  double grad_ratio = 0.0;   ///< |grad g(x*)| / |grad g(y)|
  double seconds = 0.0;      ///< wall time to compute it (0 when read from the cache)

  /// (g(x) - g*) / (g(y) - g*)
  double objectiveError(double g) const { return (g - g_star) / (g_start - g_star); }
  /// |x - x*| / |y - x*|
  double positionError(const Points& x) const {
    return (x - x_star).norm() / (start - x_star).norm();
  }
};

/// Newton's solution of the step from @p state, warm-started from @p warm_iterations of
/// chebyshev (Newton from y needs hundreds of iterations on buckling cloth; from a nearby point
/// it converges in a few, once the exact Hessian kicks in). Newton then runs to its stopping
/// test (at most 300 iterations). Results are cached in @p cache_dir (created if needed; empty
/// = no cache) under a hash of everything the step depends on.
Reference computeReference(const Model& model, const PinSet& pins, const State& state, double h,
                           const std::string& cache_dir, int warm_iterations = 2000);

}  // namespace cloth_sim::bench
