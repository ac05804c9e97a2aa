#include "fold_script.h"

#include <cmath>
#include <stdexcept>

namespace cloth_sim::tools {

FoldScript::FoldScript(const Simulation& sim, double duration) : duration_(duration) {
  if (sim.pins().size() == 0) {
    throw std::invalid_argument("--fold needs a scene with a pin (the corner it carries)");
  }
  const Pin& pin = sim.pins().pins().front();
  pin_ = pin.id;
  from_ = pin.target;
  const Points& x = sim.state().positions;
  Eigen::Index far = 0;
  (x.colwise() - x.col(pin.vertex)).colwise().squaredNorm().maxCoeff(&far);
  to_ = x.col(far);
  // The corner comes down on two layers: the lower one and the flap that trails under the
  // corner. Held lower than that (one thickness), a hard pin squeezes the flap between itself
  // and the ground, which no position can satisfy: the layers were squeezed out sideways
  // (32 x 32 under error control: 0.04 J to 12 J in the fold's last frame, flap particles
  // moving 7.9 cm in it).
  if (sim.selfContact() != nullptr) to_.z() += kLayersUnderCorner * sim.selfContact()->thickness();
  lift_ = (to_ - from_).norm() / 3.0;
}

void FoldScript::beforeStep(Simulation& sim) {
  if (released_) return;
  ++frame_;
  const double s = std::min(1.0, frame_ * sim.frameTime() / duration_);
  if (frame_ * sim.frameTime() > duration_ + 0.5 * sim.frameTime()) {
    sim.removePin(pin_);
    released_ = true;
    return;
  }
  const double along = 0.5 * (1.0 - std::cos(M_PI * s));
  sim.movePin(pin_, from_ + along * (to_ - from_) + Vec3(0, 0, lift_ * std::sin(M_PI * s)));
}

}  // namespace cloth_sim::tools
