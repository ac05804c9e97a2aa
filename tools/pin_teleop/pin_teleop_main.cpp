// pin_teleop: selects a cloth pin and moves it from the keyboard through cloth/pin_move, in the
// manner of teleop_twist_keyboard. Run it in a terminal of its own:
//   rosrun cloth_sim pin_teleop _step:=0.05
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <cstdio>
#include <vector>

#include <ros/ros.h>

#include <cloth_sim/ClothState.h>
#include <cloth_sim/PinMove.h>

#include "pin_teleop.h"

namespace {

/// Puts the terminal in raw mode (keys arrive one by one, Ctrl-C as a key) and restores it.
class RawTerminal {
 public:
  RawTerminal() {
    tcgetattr(STDIN_FILENO, &saved_);
    termios raw = saved_;
    raw.c_lflag &= ~static_cast<tcflag_t>(ICANON | ECHO | ISIG);
    raw.c_cc[VMIN] = 1;
    raw.c_cc[VTIME] = 0;
    tcsetattr(STDIN_FILENO, TCSANOW, &raw);
  }
  ~RawTerminal() { tcsetattr(STDIN_FILENO, TCSANOW, &saved_); }
  RawTerminal(const RawTerminal&) = delete;
  RawTerminal& operator=(const RawTerminal&) = delete;

  /// The next key, or -1 when none came within @p timeout_ms.
  static int readKey(int timeout_ms) {
    pollfd fd{STDIN_FILENO, POLLIN, 0};
    if (poll(&fd, 1, timeout_ms) <= 0) return -1;
    char c = 0;
    const ssize_t n = read(STDIN_FILENO, &c, 1);
    if (n == 0) return 4;  // end of input: quit like Ctrl-D
    return n == 1 ? static_cast<unsigned char>(c) : -1;
  }

 private:
  termios saved_{};
};

double now() { return ros::WallTime::now().toSec(); }

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "pin_teleop");
  ros::NodeHandle nh, pnh("~");
  const double step = pnh.param("step", 0.05);
  if (!isatty(STDIN_FILENO)) {
    ROS_FATAL("pin_teleop reads keys from a terminal: run it with rosrun in a terminal of its own");
    return 1;
  }
  std::unique_ptr<cloth_sim::node::PinTeleop> teleop;
  try {
    teleop = std::make_unique<cloth_sim::node::PinTeleop>(step);
  } catch (const std::invalid_argument& e) {
    ROS_FATAL("parameter '~step': %s", e.what());
    return 1;
  }

  std::string frame_id;
  auto on_state = [&](const cloth_sim::ClothState::ConstPtr& state) {
    frame_id = state->header.frame_id;
    std::vector<cloth_sim::node::TeleopPin> pins;
    for (const auto& p : state->pins) {
      if (p.grasp >= 0) continue;  // a grasp's frame moves its pins (the node refuses a move)
      pins.push_back({p.id, cloth_sim::Vec3(p.target.x, p.target.y, p.target.z)});
    }
    teleop->updatePins(pins, now());
  };
  ros::Subscriber sub = nh.subscribe<cloth_sim::ClothState>("cloth/state", 1, on_state);
  ros::Publisher pub = nh.advertise<cloth_sim::PinMove>("cloth/pin_move", 10);

  std::printf("%s", cloth_sim::node::PinTeleop::help().c_str());
  RawTerminal raw;
  while (ros::ok()) {
    ros::spinOnce();
    const int key = RawTerminal::readKey(100);
    if (key < 0) continue;
    const cloth_sim::node::TeleopAction action = teleop->handleKey(static_cast<char>(key), now());
    std::printf("\r\033[K%s", action.status.c_str());
    std::fflush(stdout);
    if (action.publish) {
      cloth_sim::PinMove move;
      move.id = action.pin_id;
      move.target.header.stamp = ros::Time::now();
      move.target.header.frame_id = frame_id;
      move.target.point.x = action.target.x();
      move.target.point.y = action.target.y();
      move.target.point.z = action.target.z();
      pub.publish(move);
    }
    if (action.quit) break;
  }
  std::printf("\n");
  return 0;
}
