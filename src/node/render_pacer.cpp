#include "cloth_sim/node/render_pacer.h"

#include <algorithm>
#include <cmath>

namespace cloth_sim::node {

RenderPacer::RenderPacer(double bytes_per_second, double tick)
    : budget_(bytes_per_second), tick_(tick) {}

bool RenderPacer::due(double now) const {
  // A little slack: a timer that fires a little early must not lose a whole tick.
  return now + kSlack * tick_ >= next_;
}

void RenderPacer::sent(double now, std::size_t bytes) {
  next_ = now + static_cast<double>(bytes) / budget_;
}

double RenderPacer::rateFor(std::size_t bytes) const {
  // A tick publishes when bytes / budget has passed (less the slack): every k-th tick.
  const double wait = static_cast<double>(bytes) / budget_;
  const double ticks = std::max(1.0, std::ceil(wait / tick_ - kSlack));
  return 1.0 / (ticks * tick_);
}

}  // namespace cloth_sim::node
