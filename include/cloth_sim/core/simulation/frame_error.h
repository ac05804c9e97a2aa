/// @file frame_error.h
/// The position error a frame makes, from its substeps' local truncation errors.
#pragma once

#include <vector>

#include "cloth_sim/core/linalg/types.h"

namespace cloth_sim {

/// Sums a frame's local truncation errors per particle as vectors (docs/method.md, "Error
/// control"): the error a particle carries out of the frame is the sum of what its substeps
/// added, so a systematic error (the slow motion a longer step lags) adds up over the
/// substeps, while the error of a vibration faster than the frame changes sign from substep to
/// substep and cancels. The frame's estimate is the RMS of those sums over the particles any
/// substep estimated. It is never above the sum of the substeps' own RMS errors (the triangle
/// inequality), which is what the estimate was before.
class FrameError {
 public:
  /// Starts a frame of a cloth of @p particles.
  void begin(Eigen::Index particles);
  /// Adds one substep's errors (m, 3 x N) where @p estimated is 1 (localErrors). A substep of
  /// another particle count restarts the sum.
  void add(const Points& errors, const std::vector<char>& estimated);
  /// m: the RMS over the particles estimated so far this frame of their summed error; 0 if none.
  double rms() const;

 private:
  Points sum_;                 ///< m, 3 x N
  std::vector<char> counted_;  ///< per particle: some substep of the frame estimated it
};

}  // namespace cloth_sim
