/// @file render_pacer.h
/// Which render ticks publish cloth/markers: every tick while the arrays are small, fewer as
/// they grow, so that the markers never take more than ~marker_bandwidth bytes per second
/// (an 81 x 81 cloth is 1.5 MB an array: 46 MB/s at 30 Hz, more than a subscriber reads).
/// Pure: the caller gives the time.
#pragma once

#include <cstddef>

namespace cloth_sim::node {

/// A byte budget for a periodic publisher.
class RenderPacer {
 public:
  /// @p bytes_per_second > 0; @p tick (s) is the render timer's period (1 / ~render_rate).
  RenderPacer(double bytes_per_second, double tick);

  /// Whether the tick at @p now (s, steady) may publish.
  bool due(double now) const;
  /// Records an array of @p bytes published at @p now: the next one waits bytes / budget.
  void sent(double now, std::size_t bytes);
  /// Arrays per second this pacer lets through for arrays of @p bytes: the tick rate, or less.
  double rateFor(std::size_t bytes) const;

  /// Ticks early by up to this fraction of a tick still publish (timer jitter), so the bytes
  /// per second may exceed the budget by as much: 5 % at most.
  static constexpr double kSlack = 0.05;

 private:
  double budget_, tick_;
  double next_ = -1e300;  ///< s, earliest time of the next array
};

}  // namespace cloth_sim::node
