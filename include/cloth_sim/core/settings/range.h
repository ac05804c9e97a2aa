/// @file range.h
/// The interval a tunable number must lie in (settings_table.h gives each setting one), and how
/// numbers are shown in messages.
#pragma once

#include <limits>
#include <string>

namespace cloth_sim {

/// An interval of allowed values, each end open or closed, either end possibly infinite.
/// A value is allowed when it is finite and inside.
struct Range {
  static constexpr double kInfinity = std::numeric_limits<double>::infinity();

  double min = -kInfinity;
  double max = kInfinity;
  bool min_open = false;  ///< (min, ... rather than [min, ...
  bool max_open = false;  ///< ..., max) rather than ..., max]

  /// [lo, hi]
  static constexpr Range closed(double lo, double hi) { return {lo, hi, false, false}; }
  /// >= lo
  static constexpr Range atLeast(double lo) { return {lo, kInfinity, false, false}; }
  /// > lo
  static constexpr Range above(double lo) { return {lo, kInfinity, true, false}; }

  /// Whether both ends are finite (a bounded range reads "in [a, b]", else ">= a").
  constexpr bool bounded() const { return max < kInfinity; }
  /// @p value is finite and inside.
  bool contains(double value) const;
  /// The rule as text: "in [0, 1)", "in (0, 1]", ">= 0", "> 0".
  std::string rule() const;
};

/// @p value as the messages show it, to @p significant_digits: "0.05", "100000", "1e+09", "nan".
std::string formatNumber(double value, int significant_digits = 6);

}  // namespace cloth_sim
