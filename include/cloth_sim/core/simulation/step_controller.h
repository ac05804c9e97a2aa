/// @file step_controller.h
/// Substeps per frame chosen from an estimate of the local truncation error (error control).
#pragma once

namespace cloth_sim {

/// Chooses how many implicit substeps the next frame takes so that the frame's estimated
/// position error stays below a tolerance (docs/method.md, "Error control").
///
/// A frame of F seconds taken as n substeps of h = F / n by an integrator of order p makes a
/// position error of about E(n) = n C h^(p+1) = C F^(p+1) / n^p (each substep's local error
/// summed). Given the estimate E of the frame just run with n substeps, the substeps that meet
/// the tolerance are n* = n (E / (safety tol))^(1/p). The choice is one of a fixed ladder of
/// counts (1, 2, 3, 4, 6, 8, 12, 16, 24, ...: each a factor of the solver that is kept once
/// made), and changes smoothly:
///  - up at once when the estimate is over the tolerance, by at most kMaxGrowth per frame;
///  - down one rung only after kPatience frames in a row whose error at that rung would still be
///    under kDownShare of the tolerance (hysteresis: no flip-flop between two rungs).
/// The iterations set a second floor. A substep iterates until its iteration error is under
/// its share of the tolerance, at least kLeastIterations times; a longer step converges more
/// slowly (the global step's matrix M + h^2 L strays further from the step's Hessian), and the
/// iterations a substep needs beyond the least fall about as n^-kIterationExponent with n
/// (measured: `flag` 47, 22, 12.6, 6.1, 3.9 at 8, 12, 16, 24, 32 substeps). So while a frame's
/// mean iterations per substep are over kSlowIterations, one rung more costs less, and the
/// next frame takes it; a rung down waits until the iterations it predicts there are under
/// kSlowIterations too. The frame's cost n k then settles where k nears its least.
/// It never leaves [min, max]; when the tolerance needs more than max (a frame budget or the
/// cap), the decision says so (capped), so the caller can report it. Pure arithmetic on the
/// estimates and counts it is given: the same give the same choices on any machine.
class StepController {
 public:
  /// Share of the tolerance the choice aims at when it goes up.
  static constexpr double kSafety = 0.7;
  /// Largest factor the substeps grow by in one frame.
  static constexpr int kMaxGrowth = 4;
  /// A rung down is taken when its predicted error is under this share of the tolerance...
  static constexpr double kDownShare = 0.5;
  /// ... for this many frames in a row (a quarter of a second at 60 Hz).
  static constexpr int kPatience = 15;
  /// Iterations a substep under error control takes at least (IterationError::kFirstTrusted:
  /// its stop reads no rate before the third change).
  static constexpr double kLeastIterations = 3.0;
  /// Mean iterations per substep over which the next frame takes one rung more.
  static constexpr double kSlowIterations = 1.5 * kLeastIterations;
  /// How the iterations beyond the least grow with the step: (n / n')^this from n to n' substeps.
  static constexpr double kIterationExponent = 1.5;

  /// What next() decided.
  struct Decision {
    int substeps = 1;     ///< substeps of the next frame
    bool capped = false;  ///< the tolerance needs more substeps than the maximum allows
  };

  /// @p tolerance (m, > 0 and finite): the position error a frame may make; @p order: the
  /// integrator's order p (1 implicit Euler, 2 BDF2 or implicit midpoint); substeps within
  /// [@p min_substeps, @p max_substeps] (1 <= min <= max). Throws std::invalid_argument.
  StepController(double tolerance, int order, int min_substeps, int max_substeps);

  /// The substeps of the next frame, given the frame just run with @p substeps, its error
  /// estimate @p error (m) and its mean iterations per substep @p iterations (0: not known,
  /// no iteration rule). A non-finite estimate counts as far over the tolerance.
  Decision next(int substeps, double error, double iterations = 0.0);
  /// Forgets the calm frames counted towards a rung down (after a reset or a rollback).
  void restart() { calm_frames_ = 0; }
  /// The tolerance (m) and the allowed range, for a caller that changes them live.
  double tolerance() const { return tolerance_; }
  int maxSubsteps() const { return max_; }
  /// A new maximum (a frame budget); clamped to at least the minimum.
  void setMaxSubsteps(int max_substeps);

  /// The smallest rung of the ladder that is >= @p n (n >= 1).
  static int rungAtLeast(int n);
  /// The largest rung of the ladder below @p n (1 for n <= 1).
  static int rungBelow(int n);

 private:
  double tolerance_;
  int order_;
  int min_;
  int max_;
  int calm_frames_ = 0;
};

}  // namespace cloth_sim
