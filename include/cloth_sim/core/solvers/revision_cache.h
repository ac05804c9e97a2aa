/// @file revision_cache.h
/// "Rebuild when the revision changed", written once for every solver that keeps a factor.
#pragma once

#include <cstdint>
#include <utility>

#include "cloth_sim/core/solvers/solver.h"

namespace cloth_sim {

/// Remembers which SolverInput::revision (and LinearSolver, and implicit step) some derived
/// data, such as a factorization, was built for, and rebuilds it only when they change (h, a
/// stiffness, a mass or the pin set; see SolverInput::revision).
class RevisionCache {
 public:
  /// Calls @p rebuild unless the data is already built for @p revision, @p backend and
  /// @p implicit_step (s: the h_i of M + h_i^2 L, which BDF2 changes from its first step on,
  /// see ImplicitStepProblem); returns whether it did. If @p rebuild throws, the data counts
  /// as not built.
  template <typename Rebuild>
  bool ensure(std::uint64_t revision, LinearSolver backend, double implicit_step,
              Rebuild&& rebuild) {
    if (built_ && revision_ == revision && backend_ == backend && step_ == implicit_step) {
      return false;
    }
    built_ = false;
    std::forward<Rebuild>(rebuild)();
    revision_ = revision;
    backend_ = backend;
    step_ = implicit_step;
    built_ = true;
    return true;
  }
  /// The same for data that does not depend on the implicit step.
  template <typename Rebuild>
  bool ensure(std::uint64_t revision, LinearSolver backend, Rebuild&& rebuild) {
    return ensure(revision, backend, 0.0, std::forward<Rebuild>(rebuild));
  }
  /// The same for data that does not depend on the linear solver.
  template <typename Rebuild>
  bool ensure(std::uint64_t revision, Rebuild&& rebuild) {
    return ensure(revision, built_ ? backend_ : LinearSolver::kFused,
                  std::forward<Rebuild>(rebuild));
  }

 private:
  bool built_ = false;
  std::uint64_t revision_ = 0;
  LinearSolver backend_ = LinearSolver::kFused;
  double step_ = 0.0;
};

}  // namespace cloth_sim
