#include "pin_teleop.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

namespace cloth_sim::node {
namespace {

constexpr double kMinStep = 0.001, kMaxStep = 1.0, kStepFactor = 1.25;  // m, m, -
constexpr char kCtrlC = 3, kCtrlD = 4;

}  // namespace

PinTeleop::PinTeleop(double step, double hold_time) : step_(step), hold_time_(hold_time) {
  if (!(step >= kMinStep && step <= kMaxStep)) {
    throw std::invalid_argument("teleop step must be in [0.001, 1] m");
  }
}

void PinTeleop::updatePins(const std::vector<TeleopPin>& pins, double now) {
  std::map<int, Tracked> next;
  for (const TeleopPin& p : pins) {
    auto it = pins_.find(p.id);
    if (it == pins_.end()) {
      next.emplace(p.id, Tracked{p.target, p.target});
      continue;
    }
    Tracked t = it->second;
    if (now - t.last_command >= hold_time_) t.target = p.target;
    next.emplace(p.id, t);
  }
  pins_ = std::move(next);
  if (!pins_.count(selected_)) selected_ = pins_.empty() ? -1 : pins_.begin()->first;
}

TeleopAction PinTeleop::handleKey(char key, double now) {
  const double s = step_;
  switch (key) {
    case 'i': return moveSelected(Vec3(s, 0, 0), now);
    case ',': return moveSelected(Vec3(-s, 0, 0), now);
    case 'j': return moveSelected(Vec3(0, s, 0), now);
    case 'l': return moveSelected(Vec3(0, -s, 0), now);
    case 't': return moveSelected(Vec3(0, 0, s), now);
    case 'b': return moveSelected(Vec3(0, 0, -s), now);
    case 'k': {
      if (selected_ < 0) return moveSelected(Vec3::Zero(), now);
      Tracked& t = pins_.at(selected_);
      return moveSelected(t.home - t.target, now);
    }
    case 'n': return select(+1);
    case 'p': return select(-1);
    case 'q':
    case 'z': {
      step_ = std::clamp(key == 'q' ? step_ * kStepFactor : step_ / kStepFactor, kMinStep,
                         kMaxStep);
      TeleopAction a;
      char buf[64];
      std::snprintf(buf, sizeof buf, "step %.3f m", step_);
      a.status = buf;
      return a;
    }
    case kCtrlC:
    case kCtrlD: {
      TeleopAction a;
      a.quit = true;
      a.status = "bye";
      return a;
    }
    default: {
      TeleopAction a;
      a.status = std::string("unknown key '") + key + "' (see the help above)";
      return a;
    }
  }
}

TeleopAction PinTeleop::moveSelected(const Vec3& delta, double now) {
  TeleopAction a;
  if (selected_ < 0) {
    a.status = "no pin to move (waiting for pins on cloth/state)";
    return a;
  }
  Tracked& t = pins_.at(selected_);
  t.target += delta;
  t.last_command = now;
  a.publish = true;
  a.pin_id = selected_;
  a.target = t.target;
  a.status = describeSelected();
  return a;
}

TeleopAction PinTeleop::select(int direction) {
  TeleopAction a;
  if (pins_.empty()) {
    a.status = "no pin to select (waiting for pins on cloth/state)";
    return a;
  }
  auto it = pins_.find(selected_);
  if (direction > 0) {
    it = (it == pins_.end() || std::next(it) == pins_.end()) ? pins_.begin() : std::next(it);
  } else {
    it = (it == pins_.end() || it == pins_.begin()) ? std::prev(pins_.end()) : std::prev(it);
  }
  selected_ = it->first;
  a.status = describeSelected();
  return a;
}

std::string PinTeleop::describeSelected() const {
  const Vec3& p = pins_.at(selected_).target;
  char buf[128];
  std::snprintf(buf, sizeof buf, "pin %d -> (%.3f, %.3f, %.3f) m, step %.3f m", selected_, p.x(),
                p.y(), p.z(), step_);
  return buf;
}

std::string PinTeleop::help() {
  return "Moving cloth pins (cloth/pin_move), axes of the simulation frame:\n"
         "   i / ,  : +x / -x        j / l : +y / -y        t / b : +z / -z\n"
         "   k      : back to where the pin was first seen\n"
         "   n / p  : next / previous pin\n"
         "   q / z  : step x1.25 / /1.25\n"
         "CTRL-C to quit\n";
}

}  // namespace cloth_sim::node
