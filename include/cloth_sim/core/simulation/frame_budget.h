/// @file frame_budget.h
/// Substeps per frame chosen to fit a wall-clock budget (the node's ~budget_ms).
#pragma once

namespace cloth_sim {

/// Picks how many substeps the next frame runs so that a frame takes at most a wall-clock
/// budget. On the measured accuracy fronts (docs/benchmark.md, "Accuracy against the true
/// motion") the error falls with the substeps at a fixed small iteration count, so the most
/// substeps that fit is the most accurate choice at the user's iterations; the iterations are
/// left as set.
///
/// Pure arithmetic on the frame times it is given (no clock inside): the same times give the
/// same choices. The cost of one substep is followed as an exponential average of frame time /
/// substeps; the frame after a change is not counted (it refactors the matrix for the new step).
/// Down at once when the average says the frame is over budget, up by at most a quarter after
/// kPatience frames under it, aiming at kHeadroom of the budget so that noise does not flip the
/// choice back and forth.
class FrameBudget {
 public:
  /// Frames under budget before the substeps may grow again (half a second at 60 Hz).
  static constexpr int kPatience = 30;
  /// Share of the budget the choice aims at.
  static constexpr double kHeadroom = 0.85;

  /// @p budget_s > 0 and finite: wall time (s) a frame may take; substeps stay within
  /// [@p min_substeps, @p max_substeps] (1 <= min <= max). Throws std::invalid_argument.
  FrameBudget(double budget_s, int min_substeps, int max_substeps);

  /// The substeps for the next frame, given the substeps of the frame just run and its wall
  /// time @p frame_wall_s (s). A non-finite or non-positive time changes nothing.
  int next(int substeps, double frame_wall_s);

  double budget() const { return budget_; }
  /// Averaged wall time (s) of one substep, 0 before the first counted frame.
  double substepCost() const { return cost_; }

 private:
  double budget_;
  int min_substeps_;
  int max_substeps_;
  double cost_ = 0.0;
  int frames_since_change_ = 0;
  bool skip_next_ = true;  ///< the first frame (and one after a change) pays a factorization
};

}  // namespace cloth_sim
