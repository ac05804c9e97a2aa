/// @file pin_teleop.h
/// Key-to-motion logic of pin_teleop (in the manner of teleop_twist_keyboard), apart from the
/// terminal and from ROS so it can be tested alone.
#pragma once

#include <limits>
#include <map>
#include <string>
#include <vector>

#include "cloth_sim/core/linalg/types.h"

namespace cloth_sim::node {

/// A pin as cloth/state reports it.
struct TeleopPin {
  int id = -1;
  Vec3 target = Vec3::Zero();  ///< m, in the state's frame
};

/// What a key asks the teleop to do.
struct TeleopAction {
  bool quit = false;
  bool publish = false;        ///< send @c target for pin @c pin_id on cloth/pin_move
  int pin_id = -1;
  Vec3 target = Vec3::Zero();  ///< m
  std::string status;          ///< one line for the terminal
};

/// Selects a pin and moves its target by a step per key press.
///
/// Keys (REP-103 axes, like teleop_twist_keyboard: i forward, j left):
///   i / ,  +x / -x      j / l  +y / -y      t / b  +z / -z
///   k      back to where the pin was when the teleop first saw it
///   n / p  next / previous pin (by id)
///   q / z  step x 1.25 / step / 1.25, within [1 mm, 1 m]
///   Ctrl-C or Ctrl-D quits.
/// The teleop keeps its own copy of each target: key presses accumulate without waiting for
/// the simulation. A pin's target is taken from cloth/state again once no key has moved it for
/// @c hold_time s, so a pin dragged by someone else is picked up where they left it.
class PinTeleop {
 public:
  /// @p step in m (> 0); @p hold_time in s.
  explicit PinTeleop(double step = 0.05, double hold_time = 0.5);

  /// The pins of the latest cloth/state, received at @p now (s, any monotonic clock).
  void updatePins(const std::vector<TeleopPin>& pins, double now);
  /// What @p key does at @p now (s).
  TeleopAction handleKey(char key, double now);

  int selectedPin() const { return selected_; }  ///< -1 when there is no pin
  double step() const { return step_; }          ///< m
  /// The key help text.
  static std::string help();

 private:
  struct Tracked {
    Vec3 target;
    Vec3 home;
    double last_command = -std::numeric_limits<double>::infinity();
  };
  TeleopAction moveSelected(const Vec3& delta, double now);
  TeleopAction select(int direction);
  std::string describeSelected() const;

  std::map<int, Tracked> pins_;
  int selected_ = -1;
  double step_;
  double hold_time_;
};

}  // namespace cloth_sim::node
