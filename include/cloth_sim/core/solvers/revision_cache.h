/// @file revision_cache.h
/// "Rebuild when the revision changed", written once for every solver that keeps a factor.
#pragma once

#include <cstdint>
#include <utility>

#include "cloth_sim/core/solvers/solver.h"

namespace cloth_sim {

/// Remembers which SolverInput::revision (and LinearSolver) some derived data, such as a
/// factorization, was built for, and rebuilds it only when they change (h, a stiffness, a mass
/// or the pin set; see SolverInput::revision).
class RevisionCache {
 public:
  /// Calls @p rebuild unless the data is already built for @p revision and @p backend; returns
  /// whether it did. If @p rebuild throws, the data counts as not built.
  template <typename Rebuild>
  bool ensure(std::uint64_t revision, LinearSolver backend, Rebuild&& rebuild) {
    if (built_ && revision_ == revision && backend_ == backend) return false;
    built_ = false;
    std::forward<Rebuild>(rebuild)();
    revision_ = revision;
    backend_ = backend;
    built_ = true;
    return true;
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
};

}  // namespace cloth_sim
