/// @file log_throttle.h
/// Throttles log messages per distinct text, so every kind of refused input is logged once
/// per period (ROS_*_THROTTLE throttles per call site and would hide all but the first kind).
#pragma once

#include <map>
#include <string>

namespace cloth_sim::node {

class LogThrottle {
 public:
  /// @p period in s.
  explicit LogThrottle(double period) : period_(period) {}
  /// True if @p text was not let through in the last period before @p now (s, any clock).
  bool allow(const std::string& text, double now);

 private:
  static constexpr std::size_t kMaxRemembered = 256;  ///< texts older than a period are pruned
  double period_;
  std::map<std::string, double> last_;
};

}  // namespace cloth_sim::node
