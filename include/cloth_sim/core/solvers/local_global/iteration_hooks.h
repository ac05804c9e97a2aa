/// @file iteration_hooks.h
/// The diagnostic hooks of the local/global family (tests, benchmark): objective trace and
/// iterate observer.
#pragma once

#include <functional>
#include <utility>
#include <vector>

#include "cloth_sim/core/solvers/local_global/local_global_problem.h"

namespace cloth_sim {

/// Called after iteration k (1, 2, ...) with the iterate x_k (m, all particles), the one the
/// step would return if it stopped there; returning false stops the step there.
using IterateObserver = std::function<bool(int, const Points&)>;

/// Where a local/global-family step reports its objective values and iterates.
class IterationHooks {
 public:
  /// When set, every step clears @p trace and appends g(x_k) for the initial guess and every
  /// iterate. Costs one spring pass per step. nullptr disables.
  void setObjectiveTrace(std::vector<double>* trace) { trace_ = trace; }
  /// An empty function disables. Costs a conversion to particle order per iteration.
  void setIterateObserver(IterateObserver observer) { observer_ = std::move(observer); }

  bool tracing() const { return trace_ != nullptr; }
  bool observing() const { return static_cast<bool>(observer_); }
  void clearTrace() {
    if (trace_ != nullptr) trace_->clear();
  }
  void record(double g) {
    if (trace_ != nullptr) trace_->push_back(g);
  }
  /// Calls the observer with iterate @p k, @p x (node order of @p problem); false if it asked
  /// to stop. True without an observer.
  bool observe(int k, const NodeBuffer& x, const LocalGlobalProblem& problem) {
    if (!observer_) return true;
    problem.toParticles(x, observed_);
    return observer_(k, observed_);
  }

 private:
  std::vector<double>* trace_ = nullptr;
  IterateObserver observer_;
  Points observed_;
};

}  // namespace cloth_sim
