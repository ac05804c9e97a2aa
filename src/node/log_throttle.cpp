#include "cloth_sim/node/log_throttle.h"

namespace cloth_sim::node {

bool LogThrottle::allow(const std::string& text, double now) {
  auto it = last_.find(text);
  if (it != last_.end() && now - it->second < period_) return false;
  if (last_.size() >= kMaxRemembered) {
    for (auto p = last_.begin(); p != last_.end();) {
      p = (now - p->second >= period_) ? last_.erase(p) : std::next(p);
    }
  }
  last_[text] = now;
  return true;
}

}  // namespace cloth_sim::node
